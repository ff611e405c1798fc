#include "ramtk/core/csv.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "error_message.h"
#include "ramtk/core/error.h"
#include "ramtk/core/file_io.h"

namespace ramtk {
namespace {

using testing::Message;

TEST(Csv, ParsesHeaderRowsCommentsAndLineNumbers) {
  const CsvTable t = ParseCsv("# comment\nlabel, x ,y\n\nA,1.5,2\nB,-3,4e2\n", "p.csv");
  ASSERT_EQ(t.header, (std::vector<std::string>{"label", "x", "y"}));
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t.line_numbers, (std::vector<int>{4, 5}));
  EXPECT_EQ(t.Text(1, t.Column("label")), "B");
  EXPECT_EQ(t.Number(1, t.Column("y")), 400.0);
}

TEST(Csv, ErrorsNameFileLineAndColumn) {
  const CsvTable t = ParseCsv("label,x\nA,1\nB,oops\n", "p.csv");
  EXPECT_EQ(Message([&] { t.Number(1, 1); }), "p.csv:3: field 'x': expected a number, got 'oops'");
  EXPECT_EQ(Message([&] { t.Column("z"); }), "p.csv:1: field 'z': missing column (header has 2 columns)");
  EXPECT_EQ(Message([&] { t.Integer(0, 1); }), "no error");
  EXPECT_EQ(Message([] { ParseCsv("a,b\n1,2,3\n", "q.csv"); }), "q.csv:2: expected 2 cells as in the header, got 3");
  EXPECT_EQ(Message([] { ParseCsv("a,a\n", "q.csv"); }), "q.csv:1: field 'a': duplicate column name");
  EXPECT_EQ(Message([] { ParseCsv("\n# only\n", "e.csv"); }), "e.csv: empty file: expected a header row");
}

TEST(Csv, Utf8ByteOrderMarkIsNotPartOfTheFirstColumn) {
  const CsvTable t = ParseCsv(
      "\xEF\xBB\xBF"
      "cycle,x\n1,2\n",
      "bom.csv");
  EXPECT_EQ(t.header[0], "cycle");
  EXPECT_EQ(t.Column("cycle"), 0);
  EXPECT_EQ(t.line_numbers[0], 2);
}

TEST(Csv, QuotedCellsMayHoldCommasAndQuotes) {
  const CsvTable t = ParseCsv("set,note\na,\"x, \"\"y\"\"\"\n", "q.csv");
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t.Text(0, 1), "x, \"y\"");
  EXPECT_EQ(CsvQuote("x, \"y\""), "\"x, \"\"y\"\"\"");
  EXPECT_EQ(SplitCsvLine(CsvQuote("a,b") + ",c"), (std::vector<std::string>{"a,b", "c"}));
}

TEST(FileIo, AtomicWriteReplacesAndLeavesNoTemporary) {
  const std::string path = ::testing::TempDir() + "/atomic.txt";
  WriteFileAtomically(path, "one");
  WriteFileAtomically(path, "two");
  EXPECT_EQ(ReadTextFile(path), "two");
  std::remove(path.c_str());
  EXPECT_THROW(WriteFileAtomically("/nonexistent-dir/x.txt", "x"), InputError);
  EXPECT_THROW(ReadTextFile("/nonexistent-dir/x.txt"), InputError);
}

// A folder given where a file is expected (`ramtk scan SETFOLDER` for its manifest) is named as
// one, not read as an empty document.
TEST(FileIo, AFolderIsRefusedAsOneNotReadAsEmpty) {
  const std::string dir = ::testing::TempDir() + "/a_folder";
  std::filesystem::create_directories(dir);
  EXPECT_EQ(Message([&] { ReadTextFile(dir); }), dir + ": is a folder, not a file");
  std::filesystem::remove_all(dir);
}

// The streamed form: the contents written by a callback land whole; a callback that throws
// leaves the old file as it was and no temporary beside it.
TEST(FileIo, StreamedAtomicWriteLeavesTheOldFileWhenTheWriterThrows) {
  const std::string dir = ::testing::TempDir() + "/streamed_atomic";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/out.bin";
  WriteFileAtomically(path, [](std::ostream& out) {
    for (int i = 0; i < 3; ++i) out << "block" << i << ";";
  });
  EXPECT_EQ(ReadTextFile(path), "block0;block1;block2;");
  EXPECT_THROW(WriteFileAtomically(path,
                                   [](std::ostream& out) {
                                     out << "partial";
                                     throw std::runtime_error("writer failed");
                                   }),
               std::runtime_error);
  EXPECT_EQ(ReadTextFile(path), "block0;block1;block2;");
  long files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) files += entry.is_regular_file() ? 1 : 0;
  EXPECT_EQ(files, 1);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ramtk
