// geotex options: every command's options as JSON (hidden; for tests and tools that generate front ends).

#include <fmt/format.h>

#include "cli.h"
#include "option_flags.h"

namespace geotex::cli {
namespace cmd_options {  // named, not anonymous: a unity build compiles several commands in one unit

Registrar reg{990, "options", "", [](CLI::App& app) {
  app.group("");  // hidden from `geotex --help`
  app.callback([] { fmt::print("{}\n", FlagSet::describe_all().dump(1)); });
}};

}  // namespace cmd_options
}  // namespace geotex::cli
