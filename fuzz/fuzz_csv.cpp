// The CSV table parser (every CSV format of docs/formats.md goes through it).
#include "fuzz_common.h"
#include "ramtk/core/csv.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  RAMTK_FUZZ_BODY({
    const ramtk::CsvTable t = ramtk::ParseCsv(ramtk::fuzz::Text(data, size), "fuzz.csv");
    for (std::size_t r = 0; r < t.size(); ++r)
      for (int c = 0; c < static_cast<int>(t.header.size()); ++c) {
        try {
          (void)t.Number(r, c);
        } catch (const ramtk::InputError&) {
        }
      }
    (void)ramtk::SplitCsvLine(ramtk::fuzz::Text(data, size));
  });
}
