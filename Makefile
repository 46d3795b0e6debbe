# The two commands: `make render` and `make test`. Both start with `make setup`,
# which installs only what is missing, so it is safe to run again.

SHELL := /bin/bash
APT_PACKAGES := libembree-dev libclang-dev python3-venv openexr
# For the tests only: POV-Ray 3.7 and its sample scenes and includes are the
# comparator of tests/test_povray.py and tools/povray/, never a dependency of
# the renderer (sturmray reads .pov files with its own parser).
APT_TEST_PACKAGES := povray povray-examples povray-includes
VENV := .venv
PYTHON := $(VENV)/bin/python
# The Rust tests and the Python cross-check use the same (dev) build.
DEV_BIN := target/debug/sturmray
RELEASE_BIN := target/release/sturmray

# Embree 4 on a machine whose packages give Embree 3: see tools/assemble_embree4.sh.
EMBREE4_DIR := $(CURDIR)/embree4
EMBREE4_TARGET := target/embree4

.PHONY: setup render test test-rust test-python lint bench scenes clean embree4 test-embree4 \
	fuzz check-memory wrapper-overhead povray-compare povray-fuzz povray-speed photon-radius peers embree-modes \
	sampler-study test-farm python-speed python-speed-embree4

# Installs those of the Debian packages $(1) that are missing (none: no apt-get at all).
define apt_install
	@missing=""; for p in $(1); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "install ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "installing:$$missing"; \
	  SUDO=$$( [ "$$(id -u)" = 0 ] || echo sudo ); \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $$missing; \
	fi
endef

setup: $(VENV)/.installed
	$(call apt_install,$(APT_PACKAGES) $(APT_TEST_PACKAGES))
	@command -v cargo >/dev/null || { echo "cargo not found: install Rust (https://rustup.rs)"; exit 1; }

# python3-venv must exist before the venv; the stamp is rebuilt when requirements change.
$(VENV)/.installed: requirements.txt
	@dpkg-query -W -f='$${Status}' python3-venv 2>/dev/null | grep -q "install ok installed" || { \
	  SUDO=$$( [ "$$(id -u)" = 0 ] || echo sudo ); \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq python3-venv; }
	test -x $(PYTHON) || python3 -m venv $(VENV)
	$(PYTHON) -m pip install -q -r requirements.txt
	touch $@

render: setup
	cargo build --release
	$(RELEASE_BIN) render scenes/showcase.toml -o out/showcase.exr --stats out/showcase.json

test: setup lint test-rust test-python

lint:
	cargo fmt --check
	cargo clippy --workspace --all-targets -- -D warnings

test-rust:
	cargo test --workspace

# The module cargo built in the profile folder $(1) (what maturin's build
# runs: python/'s lib with extension-module), as the package $(1)/python/sturmray:
# with $(1)/python on PYTHONPATH, pytest and tools import that build, and the
# venv's editable install (test-python's; the venv may be shared) is left alone.
# Seeds $(EMBREE4_TARGET)/$(1) (a profile folder) with hard links to what
# target/$(1) built, so only embree-sys and sturmray compile again there.
define seed_embree4
	@if [ ! -d $(EMBREE4_TARGET)/$(1) ] && [ -d target/$(1)/deps ]; then \
	  mkdir -p $(EMBREE4_TARGET)/$(1)/deps; \
	  find target/$(1)/deps -maxdepth 1 -name 'lib*' ! -name 'libsturmray*' ! -name 'libembree_sys*' \
	    -exec cp -al -t $(EMBREE4_TARGET)/$(1)/deps/ {} +; \
	  cp -a target/$(1)/build target/$(1)/.fingerprint $(EMBREE4_TARGET)/$(1)/; \
	fi
endef

define stage_module
	rm -rf $(1)/python/sturmray && mkdir -p $(1)/python
	cp -r python/sturmray $(1)/python/
	cp $(1)/lib_sturmray.so $(1)/python/sturmray/_sturmray$$($(PYTHON) -c \
	  'import sysconfig; print(sysconfig.get_config_var("EXT_SUFFIX"))')
endef

# The binary the Rust tests build (`cargo test --workspace --no-run` makes it
# for the integration tests): `cargo build` would rebuild every dependency
# whose features the dev-dependencies change, and so would a `cargo test`
# without --workspace (the Python crate's dependencies unify features across
# the workspace): minutes and gigabytes for nothing.
# The Python module (python/, docs/python.md) is built by maturin into .venv
# (editable), with the dev profile in the same target/ as cargo's builds.
test-python:
	cargo test --workspace --no-run
	VIRTUAL_ENV=$(CURDIR)/$(VENV) $(VENV)/bin/maturin develop --profile dev -m python/Cargo.toml -q
	STURMRAY_BIN=$(DEV_BIN) $(PYTHON) -m pytest tests -q

embree4:
	tools/assemble_embree4.sh $(EMBREE4_DIR)

# The whole Rust suite and the Python cross-checks, built against Embree 4 in a
# target folder of their own (the binary finds the library through its rpath).
# Its target folder starts as hard links to the dependencies `make test` built
# (same sources, same profile), so only embree-sys and sturmray compile again:
# on a fresh clone that saves CI a second build of every dependency.
# tests/python/ runs on a module built there (stage_module), which finds
# libembree4 through LD_LIBRARY_PATH (only sturmray's own binaries get the rpath).
test-embree4: setup embree4
	$(call seed_embree4,debug)
	EMBREE_DIR=$(EMBREE4_DIR) cargo test --workspace --target-dir $(EMBREE4_TARGET)
	EMBREE_DIR=$(EMBREE4_DIR) cargo test --workspace --no-run --target-dir $(EMBREE4_TARGET)
	$(EMBREE4_TARGET)/debug/sturmray info scenes/knot.toml | grep -q "^backend    Embree 4\."
	EMBREE_DIR=$(EMBREE4_DIR) cargo build --manifest-path python/Cargo.toml --features extension-module \
	  --lib --target-dir $(EMBREE4_TARGET)
	$(call stage_module,$(EMBREE4_TARGET)/debug)
	LD_LIBRARY_PATH=$(EMBREE4_DIR)/lib PYTHONPATH=$(EMBREE4_TARGET)/debug/python $(PYTHON) -c \
	  'import sturmray; s = sturmray.Scene.load("scenes/knot.toml"); assert s.backend.startswith("Embree 4."), s.backend'
	LD_LIBRARY_PATH=$(EMBREE4_DIR)/lib PYTHONPATH=$(EMBREE4_TARGET)/debug/python \
	  STURMRAY_BIN=$(EMBREE4_TARGET)/debug/sturmray $(PYTHON) -m pytest tests -q

bench: setup
	cargo build --release
	$(RELEASE_BIN) bench --json out/bench.json

# The Rust wrapper's overhead against Embree called from C on the same mesh and
# rays, on one thread (issue #5's target: at most 5%): builds the C harness
# (benches/c_harness) with cc, runs it and sturmray alternately
# WRAPPER_ROUNDS times and fails if their hit checksums differ. Not part of
# `make test` (tests/c_harness.rs checks the checksums there, without timing).
WRAPPER_ROUNDS ?= 7
wrapper-overhead: setup
	cargo build --release
	python3 tools/wrapper_overhead.py --bin $(RELEASE_BIN) --rounds $(WRAPPER_ROUNDS)

# sturmray against POV-Ray 3.7 on Debian's objects/quartic and objects/csg
# samples (issue 20 §5) at POV-Ray's default 800x600: hit masks and colour
# differences, as the Markdown table docs/img/povray/compare.md and two
# side-by-side images beside it, for the README. Exits 1 if a scene misses the
# issue's limits. Not part of `make test`, where tests/test_povray.py runs the
# same comparison at 160x120.
POVRAY_OUT := docs/img/povray
# Random CSG trees of POV-Ray's shapes drawn by both, then random hard
# algebraic surfaces with every disagreement settled by an exact root count
# (not in `make test`, which runs ten of the second's seeds).
POVRAY_FUZZ_SEEDS ?= 0:200
POVRAY_POLY_SEEDS ?= 0:200
povray-fuzz: setup
	cargo build --release
	$(PYTHON) tools/povray/fuzz_csg.py --sturmray $(RELEASE_BIN) --seeds $(POVRAY_FUZZ_SEEDS)
	$(PYTHON) tools/povray/fuzz_poly.py --sturmray $(RELEASE_BIN) --seeds $(POVRAY_POLY_SEEDS) \
	  --width 160 --height 120

povray-compare: setup
	cargo build --release
	$(PYTHON) tools/povray/compare.py --sturmray $(RELEASE_BIN) --out $(POVRAY_OUT) \
	  --width 800 --height 600 --threads 2

# Time against POV-Ray 3.7 on the objects/quartic samples at 800x600, two
# threads each, no anti-aliasing, POVRAY_ROUNDS alternated runs; prints the
# table for the README. Not part of `make test`.
POVRAY_ROUNDS ?= 3
povray-speed: setup
	cargo build --release
	$(PYTHON) tools/povray/speed.py --sturmray $(RELEASE_BIN) --rounds $(POVRAY_ROUNDS) \
	  --width 800 --height 600 --threads 2

# Issue 18's speed table: Scene.intersect against `sturmray trace` and
# embreex's run on 1M rays through a 1.3M-triangle mesh, one thread each;
# fails if the module is below 90% of the CLI or not faster than embreex.
# Before it, what add_mesh and commit add to the peak RSS (docs/python.md).
# Release builds of both; not part of `make test`.
python-speed: setup
	cargo build --release
	cargo build --release --manifest-path python/Cargo.toml --features extension-module --lib
	$(call stage_module,target/release)
	PYTHONPATH=target/release/python $(PYTHON) tools/python_memory.py
	PYTHONPATH=target/release/python $(PYTHON) tools/python_speed.py --sturmray $(RELEASE_BIN)

# The same table with the CLI and the module built against Embree 4, the
# Embree embreex's wheel bundles: the two engines on the same Embree.
python-speed-embree4: setup embree4
	$(call seed_embree4,release)
	EMBREE_DIR=$(EMBREE4_DIR) cargo build --release --target-dir $(EMBREE4_TARGET)
	EMBREE_DIR=$(EMBREE4_DIR) cargo build --release --manifest-path python/Cargo.toml \
	  --features extension-module --lib --target-dir $(EMBREE4_TARGET)
	$(call stage_module,$(EMBREE4_TARGET)/release)
	LD_LIBRARY_PATH=$(EMBREE4_DIR)/lib PYTHONPATH=$(EMBREE4_TARGET)/release/python \
	  $(PYTHON) tools/python_speed.py --sturmray $(EMBREE4_TARGET)/release/sturmray

# What the photon pass costs with its default radius on scenes/glass_floor.toml,
# a glass ball over a floor 2000 units wide (issue 15: at most 1.2x the render
# without the pass), PHOTON_ROUNDS alternated runs; prints the table for
# docs/integrators.md and fails above the limit. Not part of `make test`.
PHOTON_ROUNDS ?= 7
photon-radius:
	cargo build --release
	python3 tools/photon_radius.py --bin $(RELEASE_BIN) --rounds $(PHOTON_ROUNDS)

# sturmray against its peers (issue 15; docs/peers.md): POV-Ray 3.7 on the
# objects/quartic samples and Mitsuba 3 (llvm_ad_rgb, scalar_rgb) on the
# Cornell box; one table of ratios, also written to out/peers.md. Installs
# the peers first (tools/peers/setup.sh: Debian packages, .venv-peers). Not
# part of `make test`. Mitsuba's LLVM variant aborts with Debian 12's default
# LLVM, hence Debian's LLVM 19.
PEERS_ROUNDS ?= 3
peers: setup
	tools/peers/setup.sh
	cargo build --release
	DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 .venv-peers/bin/python \
	  tools/peers/run.py --sturmray $(RELEASE_BIN) --rounds $(PEERS_ROUNDS) --threads 2

# What Embree's own settings are worth on the Cornell box (issue 15): the
# robust flag sturmray sets against Mitsuba's settings, and one ray a call
# against packets of 8 and streams of 256, on camera, bounce and shadow rays,
# one thread (tools/peers/embree_modes.c; docs/peers.md). Not part of `make test`,
# where tests/embree_modes.rs runs it on a few rays without timing.
EMBREE_MODES_ROUNDS ?= 5
embree-modes: setup
	mkdir -p out
	cc -O2 -std=c11 tools/peers/embree_modes.c -lembree3 -lm -o out/embree_modes
	out/embree_modes scenes/cornell/cornell.obj 1048576 $(EMBREE_MODES_ROUNDS)

# What the sampler buys (issue 15): RMSE against a 4096-spp reference at 4, 16
# and 64 spp for the sobol and independent samplers on the path-traced scenes,
# 256 pixels wide; prints the table of docs/integrators.md. Not part of `make
# test`; 24 minutes on 2 cores.
sampler-study: setup
	cargo build --release
	$(PYTHON) tools/sampler_study.py --sturmray $(RELEASE_BIN) --threads 2

# docs/farm.md's recipes for real (issue 19): a one-node Slurm cluster started
# by the test (munged, slurmctld, slurmd as its own processes, state in a
# temporary folder, stopped by a trap), array jobs of tiles and frames with a
# dependent merge, a cancelled task, a failed one and a node that dies; GNU
# parallel on local slots and over ssh to an sshd of the test's own. Needs root,
# as CI runs. Its packages are installed here only: Debian enables their
# services (munge, slurmctld, slurmd, ssh) where systemd runs; the test uses
# none of them, nor their ports. Not part of `make test`; .ci/run runs it.
APT_FARM_PACKAGES := slurm-wlm munge parallel openssh-server rsync
# The dev binary `make test` already built (`cargo test --workspace --no-run`, as
# test-python): a release build here added minutes to CI for small images.
test-farm: setup
	$(call apt_install,$(APT_FARM_PACKAGES))
	cargo test --workspace --no-run
	tools/farm/test_cluster.sh $(DEV_BIN) $(PYTHON)

# Property-based fuzzing (proptest on stable Rust), not part of `make test` or
# CI: each target runs FUZZ_CASES fresh random cases, or stops after
# FUZZ_SECONDS (seven targets: at most 7 x 60 s). A failure is shrunk, printed
# and kept in tests/<crate>.proptest-regressions, which `cargo test` replays.
# fuzz_cli drives the binary end to end (scenes, rays, damaged film states).
FUZZ_CASES ?= 1000000
FUZZ_SECONDS ?= 60
FUZZ_TARGETS := fuzz_input:fuzz_scene_parser fuzz_input:fuzz_obj_loader \
	fuzz_poly:fuzz_poly_parser fuzz_poly:fuzz_root_finder fuzz_cli:fuzz_cli_end_to_end \
	hostile_poly:fuzz_roots_at_extreme_scales fuzz_poly:fuzz_certified_roots \
	fuzz_input:fuzz_pov_examples

fuzz:
	cargo test --no-run --test fuzz_input --test fuzz_poly --test fuzz_cli --test hostile_poly
	@failed=""; for target in $(FUZZ_TARGETS); do \
	  crate=$${target%%:*}; name=$${target##*:}; \
	  echo "fuzz $$name: $(FUZZ_CASES) cases or $(FUZZ_SECONDS) s"; \
	  PROPTEST_CASES=$(FUZZ_CASES) timeout $(FUZZ_SECONDS) \
	    cargo test -q --test $$crate -- --exact $$name; \
	  status=$$?; \
	  if [ $$status = 124 ]; then echo "$$name: no failure in $(FUZZ_SECONDS) s"; \
	  elif [ $$status != 0 ]; then failed="$$failed $$name"; fi; \
	done; \
	if [ -n "$$failed" ]; then echo "fuzz failures:$$failed"; exit 1; fi

# The Embree (FFI) unit tests under valgrind, then peak memory of a 5M-triangle
# mesh and of 100k analytic shapes (generated under scenes/generated/). valgrind
# and GNU time are installed here, not by `make setup`, so `make test` does not
# pay for them. The flush-to-zero test is left out: valgrind does not model the
# MXCSR FTZ/DAZ bits.
VALGRIND := valgrind --leak-check=full --show-leak-kinds=all \
	--errors-for-leak-kinds=definite,indirect --num-callers=40
check-memory: setup
	$(call apt_install,valgrind time)
	@mkdir -p out
	cargo test --lib --no-run
	bin=$$(cargo test --lib --no-run --message-format=json | python3 -c 'import json, sys; \
	  print(*[m["executable"] for m in map(json.loads, sys.stdin) \
	    if m.get("reason") == "compiler-artifact" and m["target"]["kind"] == ["lib"] \
	    and m.get("executable")])'); \
	$(VALGRIND) --log-file=out/valgrind-ffi.log $$bin accel::embree::tests --test-threads=1
	python3 tools/valgrind_check.py out/valgrind-ffi.log
	cargo build
	python3 tools/memory_report.py $(DEV_BIN) --limit-gib 24

# Regenerates the OBJ/MTL files under scenes/ (deterministic; they are committed).
scenes:
	python3 tools/make_scenes.py

clean:
	cargo clean
	rm -rf out $(EMBREE4_DIR)
