#pragma once
// Benchmark records: one flat JSON object per measured case, fields in the order they
// were added, all records of a program written as one JSON array. Shared by every
// benchmark so that the files read alike (benchmarks/suite.py and RESULTS.md read them).
#include <Kokkos_Core.hpp>
#include <fmt/core.h>
#include <fmt/os.h>

#include <string>
#include <utility>
#include <vector>

namespace dvisph::bench {

class Record {
 public:
  Record& add(const std::string& key, const std::string& text) {
    fields_.emplace_back(key, "\"" + text + "\"");
    return *this;
  }
  Record& add(const std::string& key, const char* text) { return add(key, std::string(text)); }
  Record& add(const std::string& key, long value) {
    fields_.emplace_back(key, std::to_string(value));
    return *this;
  }
  Record& add(const std::string& key, int value) { return add(key, long(value)); }
  // `decimals` digits after the point
  Record& add(const std::string& key, double value, int decimals) {
    fields_.emplace_back(key, fmt::format("{:.{}f}", value, decimals));
    return *this;
  }
  // `digits` significant digits (for values over many decades)
  Record& add_significant(const std::string& key, double value, int digits) {
    fields_.emplace_back(key, fmt::format("{:.{}g}", value, digits));
    return *this;
  }

  std::string json() const {
    std::string s = "{";
    for (std::size_t k = 0; k < fields_.size(); ++k)
      s += fmt::format("{}\"{}\": {}", k ? ", " : "", fields_[k].first, fields_[k].second);
    return s + "}";
  }

 private:
  std::vector<std::pair<std::string, std::string>> fields_;  // key, JSON value
};

inline void write_json(const std::string& path, const std::vector<Record>& records) {
  auto out = fmt::output_file(path);
  out.print("[\n");
  for (std::size_t i = 0; i < records.size(); ++i)
    out.print("  {}{}\n", records[i].json(), i + 1 < records.size() ? "," : "");
  out.print("]\n");
  out.close();
  fmt::print("wrote {}\n", path);
}

// Runs a benchmark's cases, run_all(space, records), on Serial (unless `serial` is
// false) and on the default execution space, and writes all records to `path`.
template <class RunAll>
void run_on_backends(bool serial, const std::string& path, RunAll&& run_all) {
  std::vector<Record> records;
#ifdef KOKKOS_ENABLE_SERIAL
  if (serial) run_all(Kokkos::Serial(), records);
#endif
  run_all(Kokkos::DefaultExecutionSpace(), records);
  write_json(path, records);
}

}  // namespace dvisph::bench
