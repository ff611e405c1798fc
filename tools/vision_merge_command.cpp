// ramtk merge: the results of `ramtk scan --batch LIST --shard K/N` runs joined into one results.csv.
#include <filesystem>
#include <iostream>
#include <memory>

#include "command_provenance.h"
#include "commands.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"
#include "ramtk/core/outputs.h"
#include "ramtk/vision/scan_batch.h"

namespace ramtk::tools {
namespace {

struct MergeCommandOptions {
  std::string batch;  // the batch list the shards ran
  std::string out;    // the batch folder holding results.shard-K-of-N.csv
  bool force = false;
  bool allow_errors = false;  // merge rows whose status is error or cancelled
};

int RunMerge(const MergeCommandOptions& opt, Provenance provenance) {
  const std::vector<std::string> sets = vision::ReadScanBatchList(opt.batch);
  const std::vector<std::string> shards = vision::FindShardResults(opt.out);
  const std::string target = opt.out + "/results.csv";
  std::vector<std::string> inputs = shards;
  inputs.push_back(opt.batch);
  CheckOutputAgainstInputs(target, inputs, "--out");
  // The lock a single batch run into this folder takes too: the two cannot write results.csv at once.
  const OutputLock lock(target, "--out");
  std::error_code ec;
  if (std::filesystem::exists(target, ec) && !opt.force)
    throw InputError({target, 0, "--out"}, "exists (pass --force to replace it)");
  WriteFileAtomically(target, vision::MergeScanShards(sets, shards, opt.allow_errors));
  for (const std::string& f : inputs) AddProvenanceFile(&provenance, f);
  WriteProvenanceSidecar(target, provenance);
  std::cout << "merged " << shards.size() << " shards, " << sets.size() << " sets, into " << target << "\n";
  return kExitOk;
}

}  // namespace

void RegisterMergeCommand(CLI::App& app, int* exit_code) {
  auto opt = std::make_shared<MergeCommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "merge", "Join the results of `ramtk scan --batch LIST --shard K/N` runs into one results.csv");
  sub->add_option("--batch", opt->batch, "The batch list the shards ran")->required();
  sub->add_option("--out", opt->out, "The batch folder with results.shard-K-of-N.csv")->required();
  sub->add_flag("--force", opt->force, "Replace an existing results.csv");
  sub->add_flag("--allow-errors", opt->allow_errors,
                "Merge rows whose status is error or cancelled too (by default they are refused: re-run their shard "
                "with `scan --resume`)");
  sub->callback([opt, exit_code, sub]() { *exit_code = RunMerge(*opt, CommandProvenance(sub)); });
}

}  // namespace ramtk::tools
