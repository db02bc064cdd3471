# AOCS: the two commands of the README.
#   make sil   - install everything, build, run the main job
#   make test  - install everything, build every configuration, run every test
# Other targets are the pieces they are made of.

VENV      := .venv
PY        := $(VENV)/bin/python
PRESETS   := host host-float cortex-m4f cortex-m7
JOBS      ?= 2

.PHONY: sil test setup build $(addprefix build-,$(PRESETS)) unit-test \
        image-test py-test static-analysis lint no-malloc size-report bench-laws bench \
        pil-test pil-report pil-mekf hostile mutation results demo clean bench-campaign bench-telemetry build-host-sanitize build-fuzz fuzz fuzz-smoke

setup:
	@scripts/setup.sh

build: $(addprefix build-,$(PRESETS))

$(addprefix build-,$(PRESETS)): build-%: setup
	@cmake --preset $* >/dev/null
	@cmake --build --preset $* -j $(JOBS)

# the firmware, tests and fsw_node with ASan + UBSan (no recovery): preset host-sanitize
build-host-sanitize: setup
	@cmake --preset host-sanitize >/dev/null
	@cmake --build --preset host-sanitize -j $(JOBS)

unit-test: build-host build-host-float build-host-sanitize
	ctest --preset host -j $(JOBS)
	ctest --preset host-float -j $(JOBS)
	ctest --preset host-sanitize -j $(JOBS)

# libFuzzer targets of tests/fuzz (clang): a bounded run of each in make test,
# long runs with make fuzz (FUZZ_SECONDS per target)
FUZZ_SECONDS       ?= 600
FUZZ_SMOKE_SECONDS ?= 20

build-fuzz: setup
	@cmake --preset fuzz >/dev/null
	@cmake --build --preset fuzz -j $(JOBS)

fuzz-smoke: build-fuzz
	@tests/fuzz/run.sh $(FUZZ_SMOKE_SECONDS)

fuzz: build-fuzz
	@tests/fuzz/run.sh $(FUZZ_SECONDS)

# the firmware image of each ARM target, run under QEMU (exit status 0 = pass)
image-test: build-cortex-m4f build-cortex-m7
	ctest --test-dir build/cortex-m4f/firmware/port/cortex-m --output-on-failure
	ctest --test-dir build/cortex-m7/firmware/port/cortex-m --output-on-failure

# Python structure: import order and hygiene (ruff), the layering contract of pyproject.toml (import-linter)
lint: setup
	@$(VENV)/bin/ruff check sil tools tests
	@$(VENV)/bin/lint-imports --config pyproject.toml

static-analysis: setup
	@scripts/static-analysis.sh

no-malloc: build
	@scripts/check-no-malloc.sh

# the SIL and PIL end-to-end tests need the host node (and its sanitizer build) and both ARM images
py-test: build-host build-host-sanitize build-cortex-m4f build-cortex-m7
	@scripts/run-pytest.sh

size-report: build-cortex-m4f build-cortex-m7
	@scripts/size-report.sh

# per-law step time (ns) and callgrind instructions per step (docs/benchmarks.md)
bench-laws: build-host
	@$(PY) tools/bench/bench_laws.py --json build/host/bench_laws.json

demo: build-host
	@build/host/firmware/port/posix/aocs_demo

test: build unit-test image-test static-analysis lint no-malloc py-test fuzz-smoke
	@echo "make test: all checks passed"

# main job: irassi_large with every IRASSI law, comparison table and plots
sil: build-host
	@scripts/sil-demo.sh

# lockstep real-time factor, LCM round trip, in-process plant cost
bench: build-host
	@scripts/bench-sil.sh

# Monte Carlo campaign throughput: 40 dispersed irassi_large runs on Dask against sequential
# `aocs run` processes, and one `aocs run` whole process (docs/campaigns.md)
bench-campaign: build-host
	@$(PY) -m aocs_campaign.bench --json build/host/bench_campaign.json

# a 500 s run's telemetry.parquet read into pandas, against decoding its LCM log; its HTML page (docs/benchmarks.md)
bench-telemetry: build-host
	@$(PY) -m aocs.bench_telemetry --json build/host/bench_telemetry.json

# every reference scenario, every law: docs/results.md and docs/results/*.png (~10 min)
results: build-host
	$(PY) -m aocs.cli results --out docs

# processor in the loop: the flight image on emulated Cortex-M4F / M7
pil-test: build-host build-cortex-m4f build-cortex-m7
	$(PY) -m pytest -q tests/python/aocs_pil tests/e2e/test_pil_image.py tests/e2e/test_pil_bridge.py \
		tests/e2e/test_pil_mekf.py

# instructions per step, equivalence and float accuracy figures (docs/pil.md)
pil-report: build-host build-cortex-m4f build-cortex-m7
	$(PY) -m aocs_pil.harness

# the MEKF on the images (irassi_hold_mekf, 2000 s): M4F float against the host double, instructions (docs/pil.md)
pil-mekf: build-host build-cortex-m4f build-cortex-m7
	$(PY) -m aocs_pil.mekf_check --json build/host/pil_mekf.json

# issue 25's acceptance figure: 100,000 hostile sensor frames against the sanitized fsw_node flying the wheel
# array (make test flies 4000 of them); prints the counts
hostile: build-host build-host-sanitize
	AOCS_HOSTILE_FRAMES=$${AOCS_HOSTILE_FRAMES:-100000} $(PY) -m pytest tests/e2e/test_hostile_sensors.py -q -s

# issue 25: a seeded sample of single-line mutants of firmware/src, the plant and the metrics, each run against
# the tests that can see it in a scratch copy of the tree (docs/mutation.md); not part of make test.
# Report: build/mutation/report.md and report.json; equivalent mutants: tests/mutation/equivalent.toml
MUTATION_SEED    ?= 25
MUTATION_C       ?= 60
MUTATION_PLANT   ?= 20
MUTATION_METRICS ?= 20
mutation: build-host
	$(PY) scripts/mutation/run.py --seed $(MUTATION_SEED) --c $(MUTATION_C) --plant $(MUTATION_PLANT) \
		--metrics $(MUTATION_METRICS) --jobs $(JOBS)

clean:
	rm -rf build
