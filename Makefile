# The two commands: `make render` and `make test`. Both start with `make setup`,
# which installs only what is missing, so it is safe to run again.

SHELL := /bin/bash
APT_PACKAGES := libembree-dev libclang-dev python3-venv openexr
VENV := .venv
PYTHON := $(VENV)/bin/python
# The Rust tests and the Python cross-check use the same (dev) build.
DEV_BIN := target/debug/sturmray
RELEASE_BIN := target/release/sturmray

# Embree 4 on a machine whose packages give Embree 3: see tools/assemble_embree4.sh.
EMBREE4_DIR := $(CURDIR)/embree4
EMBREE4_TARGET := target/embree4

.PHONY: setup render test test-rust test-python lint bench scenes clean embree4 test-embree4

setup: $(VENV)/.installed
	@missing=""; for p in $(APT_PACKAGES); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "install ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "installing:$$missing"; \
	  SUDO=$$( [ "$$(id -u)" = 0 ] || echo sudo ); \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $$missing; \
	fi
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
	cargo clippy --all-targets -- -D warnings

test-rust:
	cargo test

test-python:
	cargo build
	STURMRAY_BIN=$(DEV_BIN) $(PYTHON) -m pytest tests -q

embree4:
	tools/assemble_embree4.sh $(EMBREE4_DIR)

# The whole Rust suite and the Python cross-checks, built against Embree 4 in a
# target folder of their own (the binary finds the library through its rpath).
test-embree4: setup embree4
	EMBREE_DIR=$(EMBREE4_DIR) cargo test --target-dir $(EMBREE4_TARGET)
	EMBREE_DIR=$(EMBREE4_DIR) cargo build --target-dir $(EMBREE4_TARGET)
	$(EMBREE4_TARGET)/debug/sturmray info scenes/knot.toml | grep -q "^backend    Embree 4\."
	STURMRAY_BIN=$(EMBREE4_TARGET)/debug/sturmray $(PYTHON) -m pytest tests -q

bench: setup
	cargo build --release
	$(RELEASE_BIN) bench --json out/bench.json

# Regenerates the OBJ/MTL files under scenes/ (deterministic; they are committed).
scenes:
	python3 tools/make_scenes.py

clean:
	cargo clean
	rm -rf out $(EMBREE4_DIR)
