// Output safety (core/outputs.h, core/file_io.h): outputs never overwrite inputs, staged folders
// replace an old result only when the new one is complete, multi-file writes are all-or-nothing.
#include "ramtk/core/outputs.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"

namespace fs = std::filesystem;

namespace ramtk {
namespace {

fs::path Fresh(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("ramtk_outputs_test_" + std::to_string(::getpid())) / name;
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

void Touch(const fs::path& p, const std::string& text = "x") { std::ofstream(p) << text; }
std::string Read(const fs::path& p) { return ReadTextFile(p.string()); }

TEST(OutputSafety, AnOutputMayNotBeOrContainAnInput) {
  const fs::path d = Fresh("inputs");
  Touch(d / "in.csv");
  fs::create_directories(d / "set");
  Touch(d / "set" / "manifest.json");
  // The same file, spelled differently.
  EXPECT_THROW(CheckOutputAgainstInputs((d / "." / "in.csv").string(), {(d / "in.csv").string()}, "--out"), InputError);
  // A folder output that contains an input (scan SET/manifest.json --out SET).
  EXPECT_THROW(CheckOutputAgainstInputs((d / "set/").string(), {(d / "set" / "manifest.json").string()}, "--out"),
               InputError);
  // Beside the inputs, or a sibling folder whose name starts the same: fine.
  EXPECT_NO_THROW(CheckOutputAgainstInputs((d / "out.json").string(), {(d / "in.csv").string()}, "--out"));
  EXPECT_NO_THROW(CheckOutputAgainstInputs((d / "se").string(), {(d / "set" / "manifest.json").string()}, "--out"));
  EXPECT_NO_THROW(CheckOutputAgainstInputs("", {(d / "in.csv").string()}, "--out"));
  try {
    CheckOutputAgainstInputs((d / "in.csv").string(), {(d / "in.csv").string()}, "--output");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().field, "--output");
    EXPECT_NE(std::string(e.what()).find("input"), std::string::npos);
  }
}

TEST(OutputSafety, AnOutputMayNotBeAHardLinkOfAnInputNorLieInsideAnInputFolder) {
  const fs::path d = Fresh("links");
  Touch(d / "log.csv");
  fs::create_hard_link(d / "log.csv", d / "ball.csv");
  try {
    CheckOutputAgainstInputs((d / "ball.csv").string(), {(d / "log.csv").string()}, "--out");
    FAIL() << "a hard link of an input was accepted as the output";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("is the input"), std::string::npos) << e.what();
  }
  fs::create_directories(d / "in_folder");
  EXPECT_THROW(CheckOutputAgainstInputs((d / "in_folder" / "out").string(), {(d / "in_folder").string()}, "--out"),
               InputError);
  // Beside an input file (inside its folder, the folder not being an input): fine.
  EXPECT_NO_THROW(CheckOutputAgainstInputs((d / "out.csv").string(), {(d / "log.csv").string()}, "--out"));
}

TEST(OutputSafety, FifosAndDevicesAreRefusedBeforeReading) {
  const fs::path d = Fresh("special");
  ASSERT_EQ(::mkfifo((d / "fifo").c_str(), 0600), 0);
  fs::create_symlink("/dev/zero", d / "zero");
  for (const fs::path& p : {d / "fifo", d / "zero", fs::path("/dev/urandom")}) {
    try {
      ReadTextFile(p.string());  // would block (FIFO) or never end (devices)
      FAIL() << p;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(RequireRegularFile((d / "missing").string()), InputError);
  Touch(d / "plain.txt", "text");
  fs::create_symlink(d / "plain.txt", d / "link.txt");
  EXPECT_EQ(ReadTextFile((d / "link.txt").string()), "text");
}

// A pipe whose writer never closes stands for a stalled network file system: the read ends with
// an InputError naming the file and the limit instead of blocking.
TEST(OutputSafety, AReadThatDoesNotEndStopsAtTheDeadline) {
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  ASSERT_EQ(::write(fds[1], "partial", 7), 7);
  try {
    ReadToEndWithDeadline(fds[0], "/mnt/nfs/slow.csv", 0.2);
    FAIL() << "no deadline";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "/mnt/nfs/slow.csv");
    EXPECT_NE(std::string(e.what()).find("did not finish within 0.2 s"), std::string::npos) << e.what();
  }
  ::close(fds[1]);  // the helper thread then reaches the end, closes its side and ends
  // A pipe that ends is read whole.
  ASSERT_EQ(::pipe(fds), 0);
  ASSERT_EQ(::write(fds[1], "whole", 5), 5);
  ::close(fds[1]);
  EXPECT_EQ(ReadToEndWithDeadline(fds[0], "pipe", 10.0), "whole");
}

TEST(OutputSafety, ReadDeadlineFromTheEnvironmentOrSet) {
  ::unsetenv("RAMTK_READ_DEADLINE_S");
  EXPECT_EQ(ReadDeadlineSeconds(), kDefaultReadDeadlineS);
  ::setenv("RAMTK_READ_DEADLINE_S", "5", 1);
  EXPECT_EQ(ReadDeadlineSeconds(), 5.0);
  for (const char* bad : {"abc", "-3", "nan", "0", "5s"}) {
    ::setenv("RAMTK_READ_DEADLINE_S", bad, 1);
    EXPECT_EQ(ReadDeadlineSeconds(), kDefaultReadDeadlineS) << bad;
  }
  SetReadDeadline(2.5);
  EXPECT_EQ(ReadDeadlineSeconds(), 2.5);
  SetReadDeadline(1e308);
  EXPECT_EQ(ReadDeadlineSeconds(), 1e7);
  SetReadDeadline(0);
  ::unsetenv("RAMTK_READ_DEADLINE_S");
  EXPECT_EQ(ReadDeadlineSeconds(), kDefaultReadDeadlineS);
}

TEST(OutputSafety, TwoOutputsMayNotShareAPath) {
  const fs::path d = Fresh("distinct");
  EXPECT_THROW(CheckOutputsDistinct({{"--json", (d / "a").string()}, {"--series", (d / "b/../a").string()}}),
               InputError);
  EXPECT_THROW(CheckOutputsDistinct({{"--out", d.string()}, {"--json", (d / "x.json").string()}}), InputError);
  EXPECT_NO_THROW(CheckOutputsDistinct({{"--json", (d / "a").string()}, {"--series", (d / "b").string()}, {"--x", ""}}));
}

TEST(OutputSafety, StagedFolderReplacesOnlyWhenComplete) {
  const fs::path d = Fresh("staged");
  const fs::path target = d / "result";
  {
    StagedFolder s(target.string(), false);
    Touch(s.path() / "a.txt", "first");
    EXPECT_FALSE(fs::exists(target));  // nothing visible before Commit
    s.Commit();
  }
  EXPECT_EQ(Read(target / "a.txt"), "first");
  // Non-empty target without overwrite: refused, old result untouched.
  EXPECT_THROW(StagedFolder(target.string(), false), InputError);
  // An error before Commit: the temporary disappears, the old result stays.
  fs::path tmp;
  try {
    StagedFolder s(target.string(), true);
    tmp = s.path();
    Touch(s.path() / "a.txt", "second, unfinished");
    throw std::runtime_error("failure while writing");
  } catch (const std::runtime_error&) {
  }
  EXPECT_FALSE(fs::exists(tmp));
  EXPECT_EQ(Read(target / "a.txt"), "first");
  // Overwrite and commit: replaced, no sibling left behind.
  {
    StagedFolder s((target.string() + "/"), true);
    Touch(s.path() / "b.txt", "second");
    s.Commit();
  }
  EXPECT_FALSE(fs::exists(target / "a.txt"));
  EXPECT_EQ(Read(target / "b.txt"), "second");
  int entries = 0;
  for (const auto& e : fs::directory_iterator(d)) entries += e.path() != target ? 1 : 0;
  EXPECT_EQ(entries, 0);
  // A file in the way, or a missing parent: refused.
  Touch(d / "file");
  EXPECT_THROW(StagedFolder((d / "file").string(), true), InputError);
  EXPECT_THROW(StagedFolder((d / "no" / "such" / "parent").string(), false), InputError);
}

// Every entry of `d` other than `keep`: staging temporaries, old results and lock files left over.
std::vector<std::string> Leftovers(const fs::path& d, const fs::path& keep) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(d))
    if (e.path() != keep) out.push_back(e.path().filename().string());
  return out;
}

// A child process replaces an old result and is sent SIGINT at `step` of the commit; returns its
// exit status. The cleanup thread (InstallInterruptCleanup) ends the child.
int CommitInterruptedAt(const fs::path& target, detail::CommitStep step) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    InstallInterruptCleanup("outputs_test");
    StagedFolder s(target.string(), true);
    Touch(s.path() / "a.txt", "new a");
    Touch(s.path() / "b.txt", "new b");
    detail::SetCommitStepHook([step](detail::CommitStep at) {
      if (at != step) return;
      ::kill(::getpid(), SIGINT);
      ::sleep(10);  // the cleanup thread ends the process first
      ::_exit(99);
    });
    s.Commit();
    ::_exit(98);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(OutputSafety, AnInterruptedCommitLeavesTheOldOrTheNewResultWhole) {
  using Step = detail::CommitStep;
  const std::vector<std::pair<Step, std::string>> cases = {
      {Step::kStart, "old"}, {Step::kOldMovedAside, "old"}, {Step::kNewInPlace, "new"}, {Step::kOldRemoved, "new"}};
  for (const auto& [step, expected] : cases) {
    SCOPED_TRACE("step " + std::to_string(static_cast<int>(step)));
    const fs::path d = Fresh("interrupted_commit");
    const fs::path target = d / "result";
    fs::create_directories(target);
    Touch(target / "a.txt", "old a");
    Touch(target / "b.txt", "old b");
    EXPECT_EQ(CommitInterruptedAt(target, step), 128 + SIGINT);
    EXPECT_EQ(Read(target / "a.txt"), expected + " a");
    EXPECT_EQ(Read(target / "b.txt"), expected + " b");
    EXPECT_EQ(Leftovers(d, target), std::vector<std::string>{});
  }
}

TEST(OutputSafety, TwoWritersOfOneOutputAreRefused) {
  const fs::path d = Fresh("locked");
  const fs::path target = d / "result";
  {
    StagedFolder first(target.string(), true);
    try {
      StagedFolder second(target.string(), true);
      FAIL() << "a second writer of one output was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("another run is writing this output"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("process " + std::to_string(::getpid())), std::string::npos) << e.what();
    }
    EXPECT_THROW(OutputLock((d / "result/").string(), "--out"), InputError);  // spelled differently
    Touch(first.path() / "a.txt", "first");
    first.Commit();
  }
  EXPECT_EQ(Read(target / "a.txt"), "first");
  EXPECT_EQ(Leftovers(d, target), std::vector<std::string>{});
  // A lock file left by a process that died holding it does not block: the lock went with it.
  Touch(d / "result.lock", "12345\n");
  { StagedFolder again(target.string(), true); }
  EXPECT_EQ(Leftovers(d, target), std::vector<std::string>{});
}

TEST(OutputSafety, RegisteredTemporariesAreRemovedOnRequest) {
  const fs::path d = Fresh("registry");
  Touch(d / "t.tmp");
  fs::create_directories(d / "folder.partial");
  Touch(d / "folder.partial" / "x");
  RegisterTemporary(d / "t.tmp");
  RegisterTemporary(d / "folder.partial");
  RegisterTemporary(d / "never-created");
  EXPECT_EQ(RemoveRegisteredTemporaries(), 2);
  EXPECT_FALSE(fs::exists(d / "t.tmp"));
  EXPECT_FALSE(fs::exists(d / "folder.partial"));
  EXPECT_EQ(RemoveRegisteredTemporaries(), 0);  // the registry was emptied
}

TEST(OutputSafety, SeveralFilesAreWrittenAllOrNothing) {
  const fs::path d = Fresh("multi");
  Touch(d / "a.txt", "old a");
  WriteFilesAtomically({{(d / "a.txt").string(), "new a"}, {(d / "b.txt").string(), "new b"}});
  EXPECT_EQ(Read(d / "a.txt"), "new a");
  EXPECT_EQ(Read(d / "b.txt"), "new b");
  // The second file cannot be written (its folder does not exist): the first keeps its old text.
  EXPECT_THROW(WriteFilesAtomically({{(d / "a.txt").string(), "newer a"}, {(d / "missing" / "c.txt").string(), "c"}}),
               InputError);
  EXPECT_EQ(Read(d / "a.txt"), "new a");
  int entries = 0;
  for (const auto& e : fs::directory_iterator(d)) entries += 1 + 0 * e.path().empty();
  EXPECT_EQ(entries, 2);  // no temporary left
  // The same path twice is a caller error.
  EXPECT_THROW(WriteFilesAtomically({{(d / "a.txt").string(), "1"}, {(d / "a.txt").string(), "2"}}), InputError);
}

}  // namespace
}  // namespace ramtk
