#include "ramtk/core/provenance.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <memory>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"

#define XXH_INLINE_ALL
#include <xxhash.h>

namespace ramtk {
namespace {

// Incremental XXH3-128 (xxHash, header-only: XXH_INLINE_ALL), printed as xxhsum -H2 prints it
// (the canonical big-endian form in lower-case hex).
class Xxh3 {
 public:
  Xxh3() : state_(XXH3_createState(), XXH3_freeState) {
    if (!state_ || XXH3_128bits_reset(state_.get()) != XXH_OK) throw std::runtime_error("xxHash: cannot start XXH3");
  }
  void Add(const char* data, std::size_t n) {
    if (XXH3_128bits_update(state_.get(), data, n) != XXH_OK) throw std::runtime_error("xxHash: update failed");
  }
  std::string Hex() {
    XXH128_canonical_t c;
    XXH128_canonicalFromHash(&c, XXH3_128bits_digest(state_.get()));
    static const char* kHex = "0123456789abcdef";
    std::string out;
    for (unsigned char b : c.digest) {
      out.push_back(kHex[b >> 4]);
      out.push_back(kHex[b & 15]);
    }
    return out;
  }

 private:
  std::unique_ptr<XXH3_state_t, XXH_errorcode (*)(XXH3_state_t*)> state_;
};

std::string UtcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::string HostName() {
  char buf[256] = {};
  if (gethostname(buf, sizeof buf - 1) != 0) return "unknown";
  return buf;
}

}  // namespace

Provenance StartProvenance(std::vector<std::string> command, nlohmann::json options) {
  Provenance p;
  p.command = std::move(command);
  p.options = std::move(options);
  p.started_utc = UtcNow();
  p.host = HostName();
  std::error_code ec;
  p.working_directory = std::filesystem::current_path(ec).string();
  p.started = std::chrono::steady_clock::now();
  return p;
}

std::string Xxh3Of(const std::string& bytes) {
  Xxh3 h;
  h.Add(bytes.data(), bytes.size());
  return h.Hex();
}

std::string Xxh3OfFile(const std::string& path) {
  RequireRegularFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError({path, 0, ""}, "cannot open for hashing");
  Xxh3 h;
  std::vector<char> block(1 << 20);
  while (in) {
    in.read(block.data(), static_cast<std::streamsize>(block.size()));
    h.Add(block.data(), static_cast<std::size_t>(in.gcount()));
  }
  if (in.bad()) throw InputError({path, 0, ""}, "read error while hashing");
  return h.Hex();
}

void AddProvenanceInput(Provenance* provenance, const std::string& path, const std::string& recorded_as) {
  if (path.empty()) return;
  const std::string shown = recorded_as.empty() ? path : recorded_as;
  for (const ProvenanceInput& i : provenance->inputs)
    if (i.path == shown) return;
  ProvenanceInput input;
  input.path = shown;
  input.xxh3_128 = Xxh3OfFile(path);
  std::error_code ec;
  input.bytes = std::filesystem::file_size(path, ec);
  provenance->inputs.push_back(input);
}

nlohmann::ordered_json ProvenanceToJson(const Provenance& p) {
  nlohmann::ordered_json j;
  j["ramtk_version"] = p.version;
  j["git_commit"] = p.git_commit;
  j["command"] = p.command;
  j["options"] = p.options;
  nlohmann::ordered_json inputs = nlohmann::ordered_json::array();
  for (const ProvenanceInput& i : p.inputs) inputs.push_back({{"path", i.path}, {"xxh3_128", i.xxh3_128}, {"bytes", i.bytes}});
  j["inputs"] = inputs;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - p.started).count();
  j["run"] = {{"started_utc", p.started_utc},
              {"host", p.host},
              {"working_directory", p.working_directory},
              {"elapsed_s", std::round(elapsed * 1000.0) / 1000.0}};
  return j;
}

std::string WithProvenance(const std::string& json_text, const Provenance& provenance) {
  std::size_t end = json_text.find_last_not_of(" \t\r\n");
  if (end == std::string::npos || json_text[end] != '}') return json_text;
  const std::size_t before = json_text.find_last_not_of(" \t\r\n", end - 1);
  const bool empty_object = before != std::string::npos && json_text[before] == '{';
  std::string block = ProvenanceToJson(provenance).dump(2);
  std::string indented;
  for (char c : block) {
    indented.push_back(c);
    if (c == '\n') indented += "  ";
  }
  std::string out = json_text.substr(0, empty_object ? before + 1 : end);
  while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
  out += empty_object ? "\n" : ",\n";
  out += "  \"provenance\": " + indented + "\n}\n";
  return out;
}

std::pair<std::string, std::string> ProvenanceSidecar(const std::string& output_path, const Provenance& provenance) {
  const std::filesystem::path out(output_path);
  const std::string sidecar = (out.parent_path() / (out.stem().string() + ".provenance.json")).string();
  nlohmann::ordered_json j;
  j["format"] = "ramtk-provenance";
  j["version"] = 1;
  j["describes"] = out.filename().string();
  return {sidecar, WithProvenance(j.dump(2) + "\n", provenance)};
}

std::pair<std::string, std::string> FolderProvenance(const std::string& folder, const std::vector<std::string>& names,
                                                     const Provenance& provenance) {
  nlohmann::ordered_json j;
  j["format"] = "ramtk-provenance";
  j["version"] = 1;
  j["describes"] = names;
  return {(std::filesystem::path(folder) / "provenance.json").string(), WithProvenance(j.dump(2) + "\n", provenance)};
}

void WriteFolderProvenance(const std::string& folder, const Provenance& provenance) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::recursive_directory_iterator(folder)) {
    if (!e.is_regular_file()) continue;
    const std::string name = std::filesystem::relative(e.path(), folder).generic_string();
    if (name != "provenance.json") names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  const auto [path, text] = FolderProvenance(folder, names, provenance);
  WriteFileAtomically(path, text);
}

std::string ProvenanceMarkdown(const Provenance& p) {
  std::string md = "## Provenance\n\n";
  md += "- ramtk " + p.version + ", commit " + p.git_commit + "\n";
  md += "- command: `" + ShellCommandLine(p.command) + "`\n";
  for (const ProvenanceInput& i : p.inputs)
    md += "- input `" + i.path + "`: " + std::to_string(i.bytes) + " bytes, XXH3-128 " + i.xxh3_128 + "\n";
  md += "- run: started " + p.started_utc + " on " + p.host + " in " + p.working_directory + "\n\n";
  md += "Effective options:\n\n```json\n" + p.options.dump(2) + "\n```\n";
  return md;
}

std::string ShellCommandLine(const std::vector<std::string>& command) {
  std::string line;
  for (const std::string& a : command) {
    if (!line.empty()) line += ' ';
    const bool plain = !a.empty() && a.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                                         "0123456789_-+=./,:@%") == std::string::npos;
    if (plain) {
      line += a;
      continue;
    }
    line += '\'';
    for (char c : a) line += c == '\'' ? std::string("'\\''") : std::string(1, c);
    line += '\'';
  }
  return line;
}

}  // namespace ramtk
