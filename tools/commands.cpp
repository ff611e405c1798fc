#include "commands.h"

namespace ramtk::tools {

CLI::App* GetOrAddSubcommand(CLI::App& app, const std::string& name, const std::string& description) {
  auto found = app.get_subcommands([&](CLI::App* sub) { return sub->get_name() == name; });
  if (!found.empty()) return found.front();
  CLI::App* sub = app.add_subcommand(name, description);
  sub->require_subcommand(1);
  return sub;
}

CLI::App* SimulateCommand(CLI::App& app) {
  return GetOrAddSubcommand(app, "simulate", "Simulators that write data sets with their ground truth");
}

}  // namespace ramtk::tools
