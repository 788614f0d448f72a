#!/usr/bin/env bash
# Fuzzes the scene loader (dvisph::parse_scene; tests/fuzz/fuzz_scene.cpp) with libFuzzer,
# one job, for SECONDS (default 600). Builds into build-fuzz/ with clang
# (-fsanitize=fuzzer,address,undefined); the corpus grows in build-fuzz/corpus from
# scenes/*.yaml and tests/bad_scenes/*.yaml, with a dictionary of the schema's keys.
# A finding leaves its input in build-fuzz/ (crash-*, timeout-*, oom-*) and exits non-zero.
# Not part of the CMake build or CI. Needs clang++ and libclang-rt-dev, yaml-cpp and fmt.
# usage: scripts/fuzz.sh [SECONDS]
set -euo pipefail
seconds=${1:-600}
cd "$(dirname "$0")/.."
mkdir -p build-fuzz/corpus
"${CXX_FUZZ:-clang++}" -std=c++17 -g -O1 -fsanitize=fuzzer,address,undefined \
  -fno-sanitize-recover=all -I. tests/fuzz/fuzz_scene.cpp src/scene.cpp src/schema.cpp \
  -lyaml-cpp -lfmt -o build-fuzz/fuzz_scene
# every key name in docs/scenes.md, and YAML syntax
{
  grep -o '^| `[^`]*`' docs/scenes.md | tr -d '|` ' | sed 's/\[\]//g' | tr '.' '\n' | sort -u
  printf '%s\n' ': ' '- ' '[' ']' '{' '}' ', ' '&a ' '*a' '!!str ' '!!map ' '? ' '---' '...' \
    '|' '>' '~' 'null' 'true' '.inf' '-.nan' '0x1F' '1e400' '"' "'" '=' '.' '#'
} | sed 's/\\/\\\\/g; s/"/\\"/g; s/.*/"&"/' > build-fuzz/scene.dict
cd build-fuzz
# -jobs=1 -workers=1: one fuzzing process (the machine may be shared); its log,
# build-fuzz/fuzz-0.log, is printed when it ends
exec ./fuzz_scene -jobs=1 -workers=1 -max_total_time="$seconds" -timeout=10 -max_len=8192 \
  -dict=scene.dict -print_final_stats=1 corpus ../scenes ../tests/bad_scenes
