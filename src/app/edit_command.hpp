#pragma once
// `wisp edit` (the browser editor, edit/server.hpp) and `wisp schema` (the style schema as
// JSON), kept beside cli.cpp's commands.
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "app/head_args.hpp"

namespace wisp {

struct EditCommands {
    CLI::App* edit = nullptr;
    CLI::App* schema = nullptr;
    std::string style, preset, host = "127.0.0.1";
    HeadArgs head;  // --head, --head-scale, --scalp
    int port = 0;
    bool open = false;  // --open: the URL in the desktop's browser (xdg-open)
};

// Adds the two subcommands to `app`, their options bound to `args`.
void add_edit_commands(CLI::App& app, EditCommands& args);

// Runs whichever of them was given and returns its exit code; nullopt if neither was.
// Throws wisp::Error on bad input, as the other commands do.
std::optional<int> run_edit_commands(const EditCommands& args);

}  // namespace wisp
