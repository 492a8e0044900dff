# PMK Notebook — one-command set-up. Every target installs what it needs itself.
PYTHON ?= python3
VENV   ?= .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
PYTEST_ARGS ?=

.PHONY: demo test lint bench system-deps venv clean

demo: $(STAMP)  ## convert the sample, start the simulated chair and the Voilà kiosk, print the URL
	$(BIN)/pmk demo

test: $(STAMP) system-deps lint  ## install everything the tests need and run the whole suite
	$(BIN)/python -m pytest $(PYTEST_ARGS)

lint: $(STAMP)
	$(BIN)/ruff check pmk_nb tests bench conftest.py

bench: $(STAMP) system-deps  ## speed and memory figures, written to bench/results.md
	$(BIN)/pmk bench all

venv: $(STAMP)

$(STAMP): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[dev]'
	touch $(STAMP)

# Real parts the tests use: OpenSSH server (SFTP tests) and Debian's Chromium (kiosk tests).
system-deps:
	@missing=""; \
	test -x /usr/sbin/sshd || missing="$$missing openssh-server"; \
	test -x /usr/bin/chromium || missing="$$missing chromium"; \
	if [ -n "$$missing" ]; then \
	  if [ "$$(id -u)" != 0 ]; then echo "make: need root to install:$$missing (or install them yourself)"; exit 1; fi; \
	  echo "installing Debian packages:$$missing"; \
	  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $$missing >/dev/null; \
	fi

clean:
	rm -rf $(VENV) .pytest_cache .ruff_cache .hypothesis test-artifacts .demo
