#include "command_provenance.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "ramtk/core/file_io.h"

namespace ramtk::tools {
namespace {

std::vector<std::string>& CommandLine() {
  static std::vector<std::string> argv;
  return argv;
}

// "true"/"false" -> bool, a decimal number -> number, anything else -> string.
nlohmann::json Typed(const std::string& text) {
  if (text == "true") return true;
  if (text == "false") return false;
  if (!text.empty() && text.find_first_not_of("0123456789+-.eE") == std::string::npos) {
    errno = 0;
    char* end = nullptr;
    if (text.find_first_of(".eE") == std::string::npos) {
      const long long v = std::strtoll(text.c_str(), &end, 10);
      if (errno == 0 && end && *end == '\0') return v;
    } else {
      const double v = std::strtod(text.c_str(), &end);
      if (errno == 0 && end && *end == '\0' && std::isfinite(v)) return v;
    }
  }
  return text;
}

std::string NameOf(const CLI::Option* opt) {
  std::string name = opt->get_single_name();
  while (!name.empty() && name.front() == '-') name.erase(name.begin());
  return name;
}

}  // namespace

void RecordCommandLine(int argc, char** argv) {
  CommandLine().assign(argv, argv + argc);
}

nlohmann::json EffectiveOptions(CLI::App* command) {
  nlohmann::json options = nlohmann::json::object();
  for (CLI::Option* opt : command->get_options()) {
    if (opt == command->get_help_ptr() || opt == command->get_help_all_ptr()) continue;
    const std::string name = NameOf(opt);
    if (name.empty()) continue;
    if (opt->get_expected_max() == 0) {  // a flag
      bool on = opt->count() > 0;
      if (on && !opt->results().empty() && (opt->results()[0] == "false" || opt->results()[0] == "0")) on = false;
      options[name] = on;
      continue;
    }
    if (opt->count() > 0) {
      const std::vector<std::string>& r = opt->results();
      if (r.size() == 1 && opt->get_expected_max() <= 1) {
        options[name] = Typed(r[0]);
      } else {
        nlohmann::json list = nlohmann::json::array();
        for (const std::string& v : r) list.push_back(Typed(v));
        options[name] = list;
      }
      continue;
    }
    // Not given: the bound variable still holds its default.
    opt->capture_default_str();
    const std::string d = opt->get_default_str();
    if (opt->get_expected_max() > 1) {  // a list: CLI11 writes its default as "[a,b]"
      nlohmann::json list = nlohmann::json::array();
      const std::string inner = d.size() >= 2 && d.front() == '[' && d.back() == ']' ? d.substr(1, d.size() - 2) : d;
      std::size_t start = 0;
      while (!inner.empty() && start <= inner.size()) {
        const std::size_t comma = std::min(inner.find(',', start), inner.size());
        list.push_back(Typed(inner.substr(start, comma - start)));
        start = comma + 1;
      }
      options[name] = list;
    } else {
      options[name] = Typed(d);
    }
  }
  return options;
}

std::string WriteProvenanceSidecar(const std::string& output_path, const Provenance& provenance) {
  const auto [path, text] = ProvenanceSidecar(output_path, provenance);
  WriteFileAtomically(path, text);
  return path;
}

void StampOutputs(std::vector<std::pair<std::string, std::string>>* files, const Provenance& provenance) {
  std::vector<std::pair<std::string, std::string>> sidecars;
  for (auto& [path, text] : *files) {
    const std::string ext = std::filesystem::path(path).extension().string();
    if (ext == ".json") {
      text = WithProvenance(text, provenance);
    } else if (ext == ".csv" || ext == ".yaml" || ext == ".yml" || ext == ".txt") {
      sidecars.push_back(ProvenanceSidecar(path, provenance));
    }
  }
  files->insert(files->end(), sidecars.begin(), sidecars.end());
}

void AddProvenanceFile(Provenance* provenance, const std::string& path) {
  std::error_code ec;
  if (!path.empty() && std::filesystem::is_regular_file(path, ec)) AddProvenanceInput(provenance, path);
}

Provenance CommandProvenance(CLI::App* command) {
  return StartProvenance(CommandLine(), EffectiveOptions(command));
}

}  // namespace ramtk::tools
