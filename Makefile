# Two entry points for a fresh Debian 12 machine:
#   make run   installs missing packages, builds, renders the default built-in scene
#   make test  installs missing packages, builds, runs every test in ctest
BUILD ?= build
JOBS ?= 2
SCENE ?= builtin:cornell

.PHONY: deps configure build run test bench clean

deps:
	@bash tools/install_deps.sh

configure: deps
	@cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release > /dev/null

build: configure
	@cmake --build $(BUILD) -j $(JOBS)

run: build
	@mkdir -p out
	./$(BUILD)/candela render $(SCENE) --out out/default.png --width 640 --height 360 --spp 16 --frames 4 --stats out/default_stats.json

test: build
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

bench: build
	./$(BUILD)/candela bench

clean:
	rm -rf $(BUILD) out
