# Two entry points for a fresh Debian 12 machine:
#   make run   installs missing packages, builds, renders the default built-in scene
#   make test  installs missing packages, builds, runs every test in ctest
# and the checked builds, each in its own directory (docs/testing.md, "Robustness"):
#   make test-sanitize  AddressSanitizer + UndefinedBehaviorSanitizer: unit and command-line tests (CI)
#   make test-tsan      ThreadSanitizer: a few frames of every method and denoiser (CI)
#   make test-farm      the Slurm job array on a one-node cluster started for the test (CI; docs/farm.md)
#   make fuzz           libFuzzer (clang): the glTF loader and the shot-script reader, FUZZ_SECONDS each
# and the code style (.clang-format):
#   make format         formats every C++ file in place
#   make format-check   fails, listing the places, where a file is not formatted (CI)
BUILD ?= build
JOBS ?= 2
SCENE ?= builtin:cornell
SANITIZE_BUILD ?= build-sanitize
TSAN_BUILD ?= build-tsan
FUZZ_BUILD ?= build-fuzz
FUZZ_SECONDS ?= 60
# Left out under sanitizers: the convergence studies and the three slowest statistical checks of estimators
# (Bsdf.WhiteFurnace, the ReSTIR furnace, ReSTIR DI's reuse; minutes at -O1 with checks, and they only repeat
# code the other tests run) and the viewer's OpenGL tests (ViewerHeadless.*, cli.view_*): Mesa leaks in
# libraries it unloads before the leak report (no suppression can name them), and a sanitized headless
# view was seen to hang inside Mesa for 14 minutes. --timeout stops any other hang.
SANITIZE_EXCLUDE ?= ^(Convergence\.|ConvergenceShared\.|Unbiased\.|ViewerHeadless\.|cli\.view_|Bsdf\.WhiteFurnace$$|PathTracer\.RestirFurnaceMatchesClosedForm$$|DirectLightScene\.RestirDiReuseHelps$$)
SANITIZE_ENV = ASAN_OPTIONS=detect_leaks=1 \
  UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp

# The C++ files clang-format keeps; the albedo table is left as its generator prints it.
FORMAT_FILES = $(shell git ls-files '*.cpp' '*.h' | grep -v '^engine/ggx_albedo_data.h$$')

.PHONY: deps configure build run test bench clean test-sanitize test-tsan test-farm fuzz format format-check

deps:
	@bash tools/install_deps.sh

configure: deps
	@cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release > /dev/null

build: configure
	@cmake --build $(BUILD) -j $(JOBS)

run: build
	@mkdir -p out
	./$(BUILD)/candela render $(SCENE) --out out/default.png --width 640 --height 360 --spp 16 --frames 4 --stats out/default_stats.json

# Skipped tests (GTEST_SKIP: only those that need ../shared/scenes when it is absent) are counted and
# their reasons printed after ctest's summary; ctest's exit status is kept.
test: build
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS); status=$$?; \
	  bash $(CURDIR)/tools/report_skips.sh Testing/Temporary/LastTest.log; exit $$status

bench: build
	./$(BUILD)/candela bench

test-sanitize: deps
	@cmake -S . -B $(SANITIZE_BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release -DCANDELA_SANITIZE=address,undefined > /dev/null
	@cmake --build $(SANITIZE_BUILD) -j $(JOBS)
	@cd $(SANITIZE_BUILD) && $(SANITIZE_ENV) ctest --output-on-failure --timeout 600 -j $(JOBS) -E '$(SANITIZE_EXCLUDE)'; \
	  status=$$?; bash $(CURDIR)/tools/report_skips.sh Testing/Temporary/LastTest.log; exit $$status

test-tsan: deps
	@cmake -S . -B $(TSAN_BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release -DCANDELA_SANITIZE=thread -DBUILD_TESTING=OFF > /dev/null
	@cmake --build $(TSAN_BUILD) -j $(JOBS) --target candela
	@bash tools/tsan_frames.sh $(TSAN_BUILD)/candela

test-farm: build
	@bash tools/install_deps.sh slurmctld slurmd slurm-client munge
	@bash tests/slurm/farm_test.sh $(BUILD)/candela $(BUILD)/farm

fuzz: deps
	@bash tools/install_deps.sh clang-14 libclang-rt-14-dev
	@cmake -S . -B $(FUZZ_BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++-14 \
	  -DCANDELA_FUZZ=ON -DCANDELA_SANITIZE=address,undefined -DBUILD_TESTING=OFF > /dev/null
	@cmake --build $(FUZZ_BUILD) -j $(JOBS) --target candela_fuzz_gltf candela_fuzz_shot_script
	@bash tools/fuzz.sh $(FUZZ_BUILD) $(FUZZ_SECONDS)

format:
	@bash tools/install_deps.sh clang-format
	@clang-format -i $(FORMAT_FILES)

format-check:
	@bash tools/install_deps.sh clang-format
	@clang-format --dry-run --Werror $(FORMAT_FILES) && echo "format-check: $(words $(FORMAT_FILES)) files formatted"

clean:
	rm -rf $(BUILD) $(SANITIZE_BUILD) $(TSAN_BUILD) $(FUZZ_BUILD) out
