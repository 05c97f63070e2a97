#!/usr/bin/env bash
# Installs the dependencies, builds Marbles and runs every test:
#   1. the Qt Test suites (core, CLI and UI on the offscreen platform) in a RelWithDebInfo build;
#   2. the golden-hash determinism suite built with clang, so gcc and clang must agree bit for bit;
#   3. the same suites under AddressSanitizer and UndefinedBehaviorSanitizer;
#   4. the libFuzzer targets for the scene loader and the physics models, each for
#      MARBLES_FUZZ_SECONDS (default 60) seconds (the physics half from scene files, half from
#      generated crowds).
# Set MARBLES_SKIP_SANITIZERS=1 or MARBLES_FUZZ_SECONDS=0 to skip a stage while developing.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
jobs=${MARBLES_JOBS:-2}

bash tools/install-deps.sh

section() { printf '\n==== %s ====\n' "$*"; }

section "build (RelWithDebInfo)"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo
cmake --build build -j "$jobs"

section "tests"
QT_QPA_PLATFORM=offscreen ctest --test-dir build --output-on-failure -j "$jobs"

section "marbles-cli smoke run of the default preset"
./build/app/marbles-cli run preset:four-marbles --frames 200 --every 50 | tail -n 4

section "marbles-cli bench (writes build/bench.csv and build/bench.png) and stress --quick"
./build/app/marbles-cli bench --csv build/bench.csv --plot build/bench.png | tail -n 3
test -s build/bench.csv && test -s build/bench.png
./build/app/marbles-cli stress --quick | tail -n 3

section "determinism across compilers: the golden hashes with a clang build of the core"
CC=clang CXX=clang++ cmake -S . -B build-clang -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMARBLES_BUILD_UI=OFF
cmake --build build-clang -j "$jobs" --target tst_determinism_core
./build-clang/tests/tst_determinism_core | tail -n 2

if [ "${MARBLES_SKIP_SANITIZERS:-0}" != "1" ]; then
    section "tests under AddressSanitizer + UndefinedBehaviorSanitizer"
    cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Debug -DMARBLES_SANITIZE=ON
    cmake --build build-asan -j "$jobs"
    ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1 \
    LSAN_OPTIONS=suppressions=$root/tools/lsan.supp:print_suppressions=0 \
    UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    QT_QPA_PLATFORM=offscreen ctest --test-dir build-asan --output-on-failure -j "$jobs"
fi

fuzz_seconds=${MARBLES_FUZZ_SECONDS:-60}
if [ "$fuzz_seconds" != "0" ]; then
    CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DMARBLES_FUZZ=ON -DMARBLES_BUILD_UI=OFF -DMARBLES_BUILD_TESTS=OFF
    cmake --build build-fuzz -j "$jobs" --target fuzz_sceneio fuzz_physics
    mkdir -p build-fuzz/artifacts
    # Each run on a scratch copy of its seeds (the checked-in corpora stay small). The physics
    # fuzzer runs twice, half its time each, from the scene files and from the generated crowds:
    # a crowd input takes 10 to 100 times as long, so from both at once it would run few small
    # scenes. The timeout finds frames that never end; it leaves room for the slowest that do
    # (marbles wedged so that the exact model collides them thousands of times a frame, up to its
    # guards, stepped by up to four models a frame under the sanitizers: 5 s here).
    half=$(( (fuzz_seconds + 1) / 2 ))
    for run in "sceneio corpus * $fuzz_seconds" "physics physics-corpus *.json $half" \
               "physics physics-corpus *.crowd $half"; do
        read -r name folder pattern seconds <<<"$run"
        section "libFuzzer: ${name} from fuzz/${folder}/${pattern} for ${seconds}s"
        corpus=$(mktemp -d)
        cp "fuzz/${folder}"/$pattern "$corpus"/
        log=build-fuzz/fuzz_"$name".log
        status=0
        ./build-fuzz/fuzz/fuzz_"$name" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=30 \
            -artifact_prefix=build-fuzz/artifacts/ -print_final_stats=1 "$corpus" >"$log" 2>&1 || status=$?
        rm -rf "$corpus"
        if [ "$status" != "0" ]; then
            # The cause comes first in a failure's report (the target's own message, a sanitizer's,
            # or libFuzzer's), its stack after: the report from its first line, its summary, and
            # the input, last (CI shows the end of the log), compressed so that it is whole.
            first=$(grep -n -m1 -E '^(fuzz_[a-z]+:|==[0-9]+==|[^ ].*runtime error:|ALARM|ERROR: libFuzzer)' "$log" | cut -d: -f1)
            sed -n "${first:-1},\$p" "$log" | head -n 40 || true
            grep -m1 '^SUMMARY' "$log" || true
            for input in build-fuzz/artifacts/*; do
                [ -f "$input" ] || continue
                printf '\n-- %s (%s bytes): replay with base64 -d | gunzip > input && ./build-fuzz/fuzz/fuzz_%s input\n' \
                    "$input" "$(stat -c %s "$input")" "$name"
                gzip -9c "$input" | base64 -w 120
            done
            exit "$status"
        fi
        tail -n 15 "$log"
    done
fi

section "all tests passed"
