// `ramtk diagnose DATA`: hold measured data against the simulation, name the cause of what the
// model gets wrong, extend it and measure the held-out gain. The analysis is in ramtk::diagnose;
// this file only detects the kind, calls it and writes the report.
#include <filesystem>
#include <iostream>
#include <memory>

#include "command_provenance.h"
#include "commands.h"
#include "progress_printer.h"
#include "ramtk/core/error.h"
#include "ramtk/core/outputs.h"
#include "ramtk/diagnose/engine/catalogue.h"
#include "ramtk/diagnose/engine/diagnose.h"
#include "ramtk/diagnose/fringe/fringe.h"
#include "ramtk/diagnose/laser/laser.h"
#include "ramtk/diagnose/engine/report.h"
#include "ramtk/diagnose/robot/robot.h"

namespace ramtk::tools {
namespace {

int RunDiagnose(const diagnose::DiagnoseOptions& given, const std::string& kind_override, bool html, bool force,
                Provenance provenance) {
  ThrowIfInvalid(given.Validate(), "DiagnoseOptions");
  if (html && given.output_folder.empty())
    throw InputError({"", 0, "--report"}, "needs --out (the folder the report goes into)");
  // The output folder is written as a unit: everything goes into a temporary sibling
  // that replaces --out only when the report is complete; an error or an interruption leaves the
  // old folder as it was.
  std::unique_ptr<StagedFolder> staged;
  diagnose::DiagnoseOptions options = given;
  if (!given.output_folder.empty()) {
    std::vector<std::string> inputs = {given.data, given.model};
    for (const std::string& w : given.with)
      if (w.find('=') == std::string::npos) inputs.push_back(w);
    CheckOutputAgainstInputs(given.output_folder, inputs, "--out");
    for (const std::string& f : inputs) AddProvenanceFile(&provenance, f);  // a model name is no file
    // As before staging: missing parent folders are created.
    const std::filesystem::path parent = std::filesystem::path(given.output_folder).lexically_normal().parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);
    staged = std::make_unique<StagedFolder>(given.output_folder, force, "--out");
    options.output_folder = staged->path().string();
  }
  // A stated kind is not second-guessed (a tracker export has its own column names).
  diagnose::DataKind kind = kind_override == "fringe"  ? diagnose::DataKind::kFringe
                            : kind_override == "robot" ? diagnose::DataKind::kRobot
                            : kind_override == "laser" ? diagnose::DataKind::kLaser
                                                       : diagnose::DetectKind(options.data);
  diagnose::Diagnosis result;
  switch (kind) {
    case diagnose::DataKind::kRobot:
      result = diagnose::DiagnoseRobot(options);
      break;
    case diagnose::DataKind::kFringe:
      result = diagnose::DiagnoseFringe(options);
      break;
    case diagnose::DataKind::kLaser:
      result = diagnose::DiagnoseLaser(options);
      break;
  }
  if (staged) {
    diagnose::WriteDiagnosis(result, options.output_folder, provenance);
    if (html) diagnose::WriteDiagnosisHtml(result, options.output_folder, provenance);
    staged->Commit();
  }
  std::cout << diagnose::OneLine(result) << '\n';
  if (staged) std::cout << "wrote " << given.output_folder << "/report.md\n";
  if (html) std::cout << "wrote " << given.output_folder << "/report.html\n";
  return kExitOk;
}

}  // namespace

void RegisterDiagnoseCommand(CLI::App& app, int* exit_code) {
  auto options = std::make_shared<diagnose::DiagnoseOptions>();
  auto kind = std::make_shared<std::string>();
  auto html = std::make_shared<bool>(false);
  auto force = std::make_shared<bool>(false);
  CLI::App* sub = app.add_subcommand(
      "diagnose", "What the simulation gets wrong on measured data: residual structure, named cause, held-out gain");
  sub->add_option("data", options->data,
                  "Fringe manifest (.json), robot measurements CSV, laser log or sensor-frame points CSV")
      ->required();
  sub->add_option(
      "--model", options->model,
      "Current model. robot: robot YAML or kr150|bx200l|ur10 (default kr150); laser log: sensor frame JSON; "
      "fringe: unused (the ideal fringe model)");
  sub->add_option("--with", options->with,
                  "Further input, repeatable. robot: set-up JSON, monitoring CSV, thermal=traditional|none|<params>, a tracker "
                  "column file (YAML, docs/formats.md) when the data is a tracker export; "
                  "laser log: motion JSON; fringe: camera=NAME (default left), fill_factor=F and psf_sigma_px=S (the camera's "
                  "sampling kernel: box fill 0..1, 0 point sampling, default 1; Gaussian PSF sigma in camera px, default 0)");
  sub->add_option("--out", options->output_folder, "Folder for report.md, diagnosis.json and pictures");
  sub->add_flag("--report", *html,
                "Also write report.html into --out: one self-contained page with the summary, tables and "
                "interactive figures");
  sub->add_flag("--force", *force, "Replace an existing non-empty --out folder (once the new one is complete)");
  sub->add_option("--folds", options->folds, "Cross-validation folds")->capture_default_str();
  sub->add_option("--noise", options->noise,
                  "Expected noise sigma of one residual in the data's unit (0 = kind's default)");
  sub->add_option("--alpha", options->alpha, "Significance level of the structure tests")->capture_default_str();
  sub->add_option("--seed", options->seed, "Seed of anything random")->capture_default_str();
  sub->add_option("--kind", *kind, "Override the detected kind")->check(CLI::IsMember({"fringe", "robot", "laser"}));
  sub->footer("\nCauses it can name (docs/diagnose.md, the cause catalogue):\n fringe:\n" +
              diagnose::CatalogueHelp(diagnose::DataKind::kFringe) + " robot:\n" +
              diagnose::CatalogueHelp(diagnose::DataKind::kRobot) + " laser:\n" +
              diagnose::CatalogueHelp(diagnose::DataKind::kLaser));
  sub->callback([options, kind, html, force, exit_code, sub]() {
    options->progress = ProgressPrinter("steps");
    *exit_code = RunDiagnose(*options, *kind, *html, *force, CommandProvenance(sub));
  });
}

}  // namespace ramtk::tools
