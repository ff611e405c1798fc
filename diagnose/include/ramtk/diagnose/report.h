// Writing a diagnosis: JSON for programs, Markdown with pictures for people.
#pragma once

#include <string>

#include "ramtk/core/provenance.h"
#include "ramtk/diagnose/diagnosis.h"
#include "ramtk/report/html_report.h"

namespace ramtk::diagnose {

// The JSON result (cause, parameters, confidence, RMS before/after, held-out gain, candidates,
// tests). Returned as text so callers need no JSON library.
std::string DiagnosisJson(const Diagnosis& diagnosis);

// A Markdown report: summary sentence, the tests, the candidate table, the pictures.
std::string DiagnosisMarkdown(const Diagnosis& diagnosis);

// Writes `diagnosis.json` and `report.md` into `folder` (created), each atomically, both with
// `provenance` (docs/formats.md#provenance).
void WriteDiagnosis(const Diagnosis& diagnosis, const std::string& folder, const Provenance& provenance = {});

// The HTML report of a diagnosis (summary, tests, candidate table, interactive figures, pictures
// inlined from `folder`, links to the files), and writing it as `<folder>/report.html`.
report::HtmlReport DiagnosisHtml(const Diagnosis& diagnosis, const std::string& folder);
void WriteDiagnosisHtml(const Diagnosis& diagnosis, const std::string& folder, const Provenance& provenance = {});

// One line: "cause 'x' (confidence 0.93): held-out RMS 0.21 -> 0.05 mm, 94% of the excess removed".
std::string OneLine(const Diagnosis& diagnosis);

}  // namespace ramtk::diagnose
