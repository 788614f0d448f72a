// libFuzzer target for the scene loader (run by scripts/fuzz.sh). The input is a scene
// file; NUL bytes in it start `--set` overrides (YAML text \0 key=value \0 key=value).
// Parsing must succeed or throw SceneError: any other exception, a crash, a hang or
// undefined behaviour is a finding.
#include "src/scene.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> pieces;
  for (std::size_t start = 0;;) {
    const std::size_t end = input.find('\0', start);
    pieces.push_back(input.substr(start, end - start));
    if (end == std::string::npos) break;
    start = end + 1;
  }
  const std::vector<std::string> overrides(pieces.begin() + 1, pieces.end());
  try {
    dvisph::parse_scene(pieces[0], overrides);
  } catch (const dvisph::SceneError&) {
  }
  return 0;
}
