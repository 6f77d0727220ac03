#pragma once
// The `wisp` command line: generate, head, info, convert (DESIGN.md "Interfaces").
// Exit codes: 0 success, 1 bad input (message names the file, field and reason),
// 2 usage error.

namespace wisp {

// Runs the command line; returns the process exit code. Never throws.
int run_cli(int argc, char** argv);

}  // namespace wisp
