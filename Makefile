# Two entry points for a fresh Debian 12 machine (see README.md):
#   make run   install missing packages, build Release into build/, generate the default dataset
#   make test  the same set-up, then the whole CTest suite
# Extra: make test-asan (unit tests under AddressSanitizer + UBSan), make bench (bench/), make format,
#        make docs (regenerate docs/SCENARIO.md from the scenario schema).
.PHONY: run test deps build test-asan bench format docs clean

deps:
	@scripts/install-deps.sh

build: deps
	cmake --preset release
	cmake --build --preset release

run: build
	build/bin/trainsim generate --out output --force

test: build
	ctest --preset release

test-asan: deps
	cmake --preset asan
	cmake --build --preset asan
	ctest --preset asan

bench: build
	@for b in build/bin/bench_*; do echo "== $$b"; $$b; done

format:
	git ls-files '*.cpp' '*.hpp' '*.h' '*.inc' | xargs clang-format -i

docs: build
	build/bin/trainsim schema > docs/SCENARIO.md

clean:
	rm -rf build build-debug build-asan
