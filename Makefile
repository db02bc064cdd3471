# AOCS: the two commands of the README.
#   make sil   - install everything, build, run the main job
#   make test  - install everything, build every configuration, run every test
# Other targets are the pieces they are made of.

VENV      := .venv
PY        := $(VENV)/bin/python
PRESETS   := host host-float cortex-m4f cortex-m7
JOBS      ?= 2

.PHONY: sil test setup build $(addprefix build-,$(PRESETS)) unit-test \
        image-test py-test static-analysis no-malloc size-report bench-laws demo clean

setup:
	@scripts/setup.sh

build: $(addprefix build-,$(PRESETS))

$(addprefix build-,$(PRESETS)): build-%: setup
	@cmake --preset $* >/dev/null
	@cmake --build --preset $* -j $(JOBS)

unit-test: build-host build-host-float
	ctest --preset host -j $(JOBS)
	ctest --preset host-float -j $(JOBS)

# the firmware image of each ARM target, run under QEMU (exit status 0 = pass)
image-test: build-cortex-m4f build-cortex-m7
	ctest --test-dir build/cortex-m4f/firmware/port/cortex-m --output-on-failure
	ctest --test-dir build/cortex-m7/firmware/port/cortex-m --output-on-failure

static-analysis: setup
	@scripts/static-analysis.sh

no-malloc: build
	@scripts/check-no-malloc.sh

py-test: build-host
	@scripts/run-pytest.sh

size-report: build-cortex-m4f build-cortex-m7
	@scripts/size-report.sh

# per-law step time (ns) and callgrind instructions per step (docs/benchmarks.md)
bench-laws: build-host
	@$(PY) tools/bench/bench_laws.py --json build/host/bench_laws.json

demo: build-host
	@build/host/firmware/port/posix/aocs_demo

test: build unit-test image-test static-analysis no-malloc py-test
	@echo "make test: all checks passed"

sil: build-host demo

clean:
	rm -rf build
