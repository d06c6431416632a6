// ewis: the command line of ewis-inspect. Parses options and dispatches to one subcommand; maps errors to
// the exit codes of CONTRACT.md (2: bad usage or input, 3: could not finish, 4: internal error).
#include <tbb/global_control.h>

#include <iostream>
#include <memory>
#include <new>

#include "common.hpp"
#include "ewis/core/error.hpp"

int main(int argc, char** argv) {
  using namespace ewis::cli;
  CLI::App app{"ewis-inspect: inspect aircraft wiring (EWIS) from 3D scans against the CAD model"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "ewis 0.1.0");
  CommonOptions common;
  std::vector<Command> commands = {
      add_inspect(app, common), add_plan(app, common),     add_tubes(app, common),
      add_info(app, common),    add_filter(app, common),   add_register(app, common),
      add_simulate(app, common), add_evaluate(app, common),
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "ewis: " << e.what() << " (see ewis --help)\n";
    return 2;
  }
  std::unique_ptr<tbb::global_control> threads;
  if (common.threads > 0)
    threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, common.threads);
  try {
    for (auto& c : commands)
      if (c.app->parsed()) return c.run();
  } catch (const ewis::InputError& e) {
    std::cerr << "ewis: " << e.what() << "\n";
    return 2;
  } catch (const ewis::ProcessingError& e) {
    std::cerr << "ewis: " << e.what() << "\n";
    return 3;
  } catch (const std::bad_alloc&) {
    std::cerr << "ewis: out of memory\n";
    return 4;
  } catch (const std::exception& e) {
    std::cerr << "ewis: internal error: " << e.what() << "\n";
    return 4;
  }
  return 2;
}
