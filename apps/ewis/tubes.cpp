// ewis tubes: see CONTRACT.md. (Placeholder until its stage lands: the command exists but reports that it
// is not available yet, exit 3.)
#include "common.hpp"
#include "ewis/core/error.hpp"

namespace ewis::cli {

Command add_tubes(CLI::App& root, CommonOptions& common) {
  Command cmd;
  cmd.app = root.add_subcommand("tubes", "(not available yet)");
  add_common_options(cmd.app, common);
  cmd.run = [] () -> int { throw ProcessingError("'tubes' is not available in this build yet"); };
  return cmd;
}

}  // namespace ewis::cli
