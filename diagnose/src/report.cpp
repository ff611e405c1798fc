#include "ramtk/diagnose/report.h"

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "ramtk/core/file_io.h"

namespace ramtk::diagnose {
namespace {

nlohmann::json Finite(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json MapJson(const std::map<std::string, double>& m) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [k, v] : m) j[k] = Finite(v);
  return j;
}

std::string Fixed(double v, int digits) {
  std::ostringstream out;
  out << std::setprecision(digits) << v;
  return out.str();
}

}  // namespace

std::string DiagnosisJson(const Diagnosis& d) {
  nlohmann::json j;
  j["kind"] = DataKindName(d.kind);
  j["data"] = d.data;
  j["model"] = d.model;
  j["unit"] = d.unit;
  j["num_residuals"] = d.num_residuals;
  j["noise_floor_rms"] = Finite(d.noise_floor_rms);
  if (!d.noise_model.empty())
    j["noise_model"] = {{"parameters", MapJson(d.noise_model)}, {"sigmas", MapJson(d.noise_model_sigmas)}};
  j["residual_rms"] = Finite(d.residual_rms);
  j["structure_found"] = d.structure_found;
  j["structure_p_value"] = Finite(d.structure_p_value);
  j["findings"] = d.findings;
  j["cause"] = d.cause;
  j["parameters"] = MapJson(d.parameters);
  j["sigmas"] = MapJson(d.sigmas);
  j["confidence"] = Finite(d.confidence);
  if (!d.explaining_variable.empty()) j["explaining_variable"] = d.explaining_variable;
  if (!d.partial.empty()) j["partial"] = d.partial;
  if (!d.look_alikes.empty()) j["look_alikes"] = d.look_alikes;
  if (!d.separate_with.empty()) j["separate_with"] = d.separate_with;
  if (!d.causes.empty()) {
    nlohmann::json causes = nlohmann::json::array();
    for (const CauseStep& c : d.causes) {
      causes.push_back({{"effect", c.effect},
                        {"num_parameters", c.num_parameters},
                        {"heldout_rms_before", Finite(c.rms_before)},
                        {"heldout_rms_after", Finite(c.rms_after)},
                        {"excess_removed", Finite(c.excess_removed)},
                        {"parameters", MapJson(c.parameters)},
                        {"sigmas", MapJson(c.sigmas)}});
    }
    j["causes"] = causes;
  }
  j["heldout"] = {{"rms_before", Finite(d.rms_before)},
                  {"rms_after", Finite(d.rms_after)},
                  {"excess_removed", Finite(d.excess_removed)}};
  nlohmann::json candidates = nlohmann::json::array();
  for (const CandidateFit& c : d.candidates) {
    candidates.push_back({{"effect", c.effect},
                          {"num_parameters", c.num_parameters},
                          {"parameters", MapJson(c.parameters)},
                          {"sigmas", MapJson(c.sigmas)},
                          {"train_rms", Finite(c.train_rms)},
                          {"heldout_rms", Finite(c.heldout_rms)},
                          {"heldout_count", c.heldout_count},
                          {"score", Finite(c.score)},
                          {"weight", Finite(c.weight)}});
    if (c.absorbed_share >= 0) candidates.back()["absorbed_share"] = Finite(c.absorbed_share);
    if (c.signature_cos >= 0) candidates.back()["signature_cos"] = Finite(c.signature_cos);
    if (!c.implausible.empty()) candidates.back()["implausible"] = c.implausible;
  }
  j["candidates"] = candidates;
  nlohmann::json pictures = nlohmann::json::array();
  for (const Picture& p : d.pictures) pictures.push_back({{"file", p.file}, {"caption", p.caption}});
  j["pictures"] = pictures;
  return j.dump(2) + "\n";
}

std::string OneLine(const Diagnosis& d) {
  std::ostringstream out;
  out << DataKindName(d.kind) << ": ";
  if (d.cause == kNoEffect) {
    out << "no effect: residual RMS " << Fixed(d.residual_rms, 4) << " " << d.unit << " against a noise floor of "
        << Fixed(d.noise_floor_rms, 4) << " " << d.unit
        << (d.structure_found ? " (structure, but no extension pays)" : " (white)");
    return out.str();
  }
  if (d.causes.size() > 1) {
    out << "causes";
    for (size_t i = 0; i < d.causes.size(); ++i) {
      out << (i ? " + '" : " '") << d.causes[i].effect << "' (" << Fixed(100.0 * d.causes[i].excess_removed, 3) << "%)";
    }
  } else {
    out << "cause '" << d.cause << "'";
  }
  if (d.cause == kUnexplained && !d.explaining_variable.empty())
    out << " (explained by " << d.explaining_variable << ")";
  if (!d.look_alikes.empty()) {
    out << " {";
    for (size_t i = 0; i < d.look_alikes.size(); ++i) out << (i ? ", " : "") << d.look_alikes[i];
    out << "}";
  }
  if (!d.partial.empty()) {
    out << " (partly";
    for (size_t i = 0; i < d.partial.size(); ++i) out << (i ? " + " : " ") << d.partial[i];
    out << ")";
  }
  out << " (confidence " << Fixed(d.confidence, 3) << "): held-out RMS " << Fixed(d.rms_before, 4) << " -> "
      << Fixed(d.rms_after, 4) << " " << d.unit << ", " << Fixed(100.0 * d.excess_removed, 3)
      << "% of the excess over the noise floor removed";
  return out.str();
}

std::string DiagnosisMarkdown(const Diagnosis& d) {
  std::ostringstream md;
  md << "# Diagnosis: " << DataKindName(d.kind) << " data\n\n";
  md << "- data: `" << d.data << "`\n- model: " << d.model << "\n- residuals: " << d.num_residuals << " (" << d.unit
     << ")\n\n";
  md << "**" << OneLine(d) << "**\n\n";
  md << "## Residual of the current model\n\n";
  md << "RMS " << Fixed(d.residual_rms, 4) << " " << d.unit << "; expected from the noise alone "
     << Fixed(d.noise_floor_rms, 4) << " " << d.unit << ". "
     << (d.structure_found ? "The residual has structure" : "The residual is consistent with the noise")
     << " (smallest corrected p-value " << Fixed(d.structure_p_value, 3) << ").\n\n";
  for (const std::string& f : d.findings) md << "- " << f << "\n";
  md << "\n## Candidate extensions (cross-validated)\n\n";
  md << "| effect | extra parameters | train RMS | held-out RMS | score | weight | estimates |\n";
  md << "|---|---|---|---|---|---|---|\n";
  for (const CandidateFit& c : d.candidates) {
    md << "| `" << c.effect << "` | " << c.num_parameters << " | " << Fixed(c.train_rms, 4) << " | "
       << Fixed(c.heldout_rms, 4) << " | " << Fixed(c.score, 6) << " | " << Fixed(c.weight, 3) << " | ";
    bool first = true;
    for (const auto& [k, v] : c.parameters) {
      md << (first ? "" : ", ") << k << " = " << Fixed(v, 4);
      const auto s = c.sigmas.find(k);
      if (s != c.sigmas.end()) md << " ± " << Fixed(s->second, 2);
      first = false;
    }
    md << " |\n";
  }
  if (!d.pictures.empty()) {
    md << "\n## Pictures\n\n";
    for (const Picture& p : d.pictures) {
      if (p.file.empty()) {
        md << "- (" << p.caption << ": not drawn, gnuplot missing; see report.html)\n\n";
        continue;
      }
      md << "![" << p.caption << "](" << p.file << ")\n\n" << p.caption << "\n\n";
    }
  }
  return md.str();
}

report::HtmlReport DiagnosisHtml(const Diagnosis& d, const std::string& folder) {
  report::HtmlReport html("Diagnosis: " + std::string(DataKindName(d.kind)) + " data");
  html.KeyValues({{"data", d.data}, {"model", d.model}, {"residuals", std::to_string(d.num_residuals) + " (" + d.unit + ")"}});
  html.Paragraph(OneLine(d));
  html.Section("Residual of the current model");
  html.KeyValues({{"residual RMS (" + d.unit + ")", Fixed(d.residual_rms, 4)},
                  {"noise floor RMS (" + d.unit + ")", Fixed(d.noise_floor_rms, 4)},
                  {"structure", d.structure_found ? "yes" : "no (consistent with the noise)"},
                  {"smallest corrected p-value", Fixed(d.structure_p_value, 3)}});
  if (!d.findings.empty()) {
    std::vector<std::vector<std::string>> rows;
    for (const std::string& f : d.findings) rows.push_back({f});
    html.Table({"finding"}, rows);
  }
  html.Section("Candidate extensions (cross-validated)");
  std::vector<std::vector<std::string>> rows;
  for (const CandidateFit& c : d.candidates) {
    std::string est;
    for (const auto& [k, v] : c.parameters) {
      est += (est.empty() ? "" : ", ") + k + " = " + Fixed(v, 4);
      const auto sg = c.sigmas.find(k);
      if (sg != c.sigmas.end()) est += " ± " + Fixed(sg->second, 2);
    }
    rows.push_back({c.effect, std::to_string(c.num_parameters), Fixed(c.train_rms, 4), Fixed(c.heldout_rms, 4),
                    Fixed(c.score, 6), Fixed(c.weight, 3), est});
  }
  html.Table({"effect", "extra parameters", "train RMS (" + d.unit + ")", "held-out RMS (" + d.unit + ")", "score",
              "weight", "estimates"},
             rows);
  if (!d.pictures.empty()) {
    html.Section("Pictures");
    int k = 0;
    for (const Picture& p : d.pictures) {
      if (p.figure) {
        html.AddFigure(*p.figure);
      } else if (!p.file.empty()) {
        const std::string stem = std::filesystem::path(p.file).stem().string();
        html.AddImage("image-" + std::to_string(k) + "-" + stem, (std::filesystem::path(folder) / p.file).string(),
                      p.caption);
      }
      ++k;
    }
  }
  html.Section("Files");
  std::vector<std::pair<std::string, std::string>> links = {{"diagnosis (JSON)", "diagnosis.json"},
                                                            {"report (Markdown)", "report.md"}};
  for (const Picture& p : d.pictures)
    if (!p.file.empty()) links.push_back({p.caption.substr(0, 60) + (p.caption.size() > 60 ? "…" : ""), p.file});
  html.Links(links);
  return html;
}

void WriteDiagnosisHtml(const Diagnosis& diagnosis, const std::string& folder, const Provenance& provenance) {
  report::HtmlReport page = DiagnosisHtml(diagnosis, folder);
  page.AddProvenance(provenance);
  page.Write((std::filesystem::path(folder) / "report.html").string());
}

void WriteDiagnosis(const Diagnosis& diagnosis, const std::string& folder, const Provenance& provenance) {
  std::filesystem::create_directories(folder);
  const std::filesystem::path dir(folder);
  WriteFileAtomically((dir / "diagnosis.json").string(), WithProvenance(DiagnosisJson(diagnosis), provenance));
  WriteFileAtomically((dir / "report.md").string(),
                      DiagnosisMarkdown(diagnosis) + "\n" + ProvenanceMarkdown(provenance));
}

}  // namespace ramtk::diagnose
