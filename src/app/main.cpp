#include "app/cli.hpp"

int main(int argc, char** argv) {
    return wisp::run_cli(argc, argv);
}
