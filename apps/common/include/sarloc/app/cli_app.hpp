#pragma once
// CLI11's App, declared only. <CLI/CLI.hpp> (CLI11 2.1, header-only) compiles about 4 s of
// code into every file that includes it, so only the files that build a command line include
// it; headers that take a CLI::App& include this one.
namespace CLI {
class App;
}  // namespace CLI
