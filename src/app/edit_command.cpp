#include "app/edit_command.hpp"

#include <spawn.h>
#include <sys/wait.h>

#include <csignal>
#include <iostream>
#include <thread>

#include "core/error.hpp"
#include "edit/server.hpp"
#include "edit/wire.hpp"
#include "groom/style_toml.hpp"

extern char** environ;

namespace wisp {
namespace {

// Opens `url` in the desktop's browser with xdg-open (which returns at once); says so
// plainly when there is no xdg-open or it fails (a machine without a desktop).
void open_in_browser(const std::string& url) {
    const char* argv[] = {"xdg-open", url.c_str(), nullptr};
    // The browser gets the signals this process blocks for its own sigwait.
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    sigset_t none;
    sigemptyset(&none);
    posix_spawnattr_setsigmask(&attr, &none);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK);
    pid_t pid = 0;
    const int spawned =
        posix_spawnp(&pid, "xdg-open", nullptr, &attr, const_cast<char**>(argv), environ);
    posix_spawnattr_destroy(&attr);
    if (spawned != 0) {
        std::cerr << "wisp edit: --open: there is no xdg-open on this machine (install "
                     "xdg-utils, or open the URL below in a browser yourself)\n";
        return;
    }
    // Some browsers keep xdg-open waiting until they close: it is reaped on a thread of its
    // own, so that Ctrl-C still stops the editor.
    std::thread([pid] {
        int status = 0;
        if (waitpid(pid, &status, 0) == pid && !(WIFEXITED(status) && WEXITSTATUS(status) == 0))
            std::cerr << "wisp edit: --open: xdg-open found no browser to open (exit "
                      << (WIFEXITED(status) ? WEXITSTATUS(status) : -1)
                      << "); open the URL above yourself\n";
    }).detach();
}

}  // namespace

void add_edit_commands(CLI::App& app, EditCommands& args) {
    args.edit = app.add_subcommand(
        "edit",
        "Edit a hairstyle in the browser: serves the editor on 127.0.0.1 and prints its URL");
    args.edit->add_option("style", args.style, "Style file (TOML) to start from")
        ->check(CLI::ExistingFile);
    args.edit->add_option("--preset", args.preset, "A shipped preset to start from");
    args.head.add_to(args.edit);
    args.edit
        ->add_option("--host", args.host,
                     "Address to listen on; anything but 127.0.0.1 lets other machines "
                     "reach the editor")
        ->capture_default_str();
    args.edit->add_option("--port", args.port, "Port (0: a free one)")
        ->check(CLI::Range(0, 65535))
        ->capture_default_str();
    args.edit->add_flag("--open", args.open,
                        "Open the editor in the desktop's browser (xdg-open) once it runs");
    args.schema = app.add_subcommand(
        "schema", "Print the style schema (every field's path, type, range, unit, doc) as JSON");
}

std::optional<int> run_edit_commands(const EditCommands& args) {
    if (args.schema && *args.schema) {
        std::cout << schema_json().dump(2) << '\n';
        return 0;
    }
    if (!args.edit || !*args.edit) return std::nullopt;
    if (!args.style.empty() && !args.preset.empty())
        fail("give a style file or --preset, not both");
    Style style;
    std::filesystem::path base_dir = std::filesystem::current_path();
    if (!args.style.empty()) {
        style = load_style(args.style);
        base_dir = std::filesystem::absolute(args.style).parent_path();
    } else {
        style = load_preset(args.preset.empty() ? "default" : args.preset);
    }
    args.head.apply(style);
    if (args.host != "127.0.0.1" && args.host != "localhost")
        std::cerr << "wisp: warning: listening on " << excerpt(args.host)
                  << ": other machines may reach the editor (the token still guards it)\n";

    // Ctrl-C and SIGTERM are taken by this thread alone (sigwait), so the server's threads
    // are never interrupted and it stops cleanly.
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &signals, nullptr);

    EditOptions options;
    if (!args.style.empty())
        options.document = std::filesystem::path(args.style).filename().string();
    options.host = args.host;
    options.port = args.port;
    EditServer server(std::move(style), base_dir, options);
    server.start();
    if (!editor_front_end_built())
        std::cerr << "wisp: warning: this wisp was built without Node.js: the page says how to "
                     "build the editor's front end\n";
    std::cout << "wisp edit: " << server.url() << "\n(Ctrl-C stops it)" << std::endl;
    if (args.open) open_in_browser(server.url());
    int signal = 0;
    sigwait(&signals, &signal);
    std::cerr << "wisp edit: stopping\n";
    server.stop();
    return 0;
}

}  // namespace wisp
