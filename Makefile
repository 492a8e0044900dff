# PMK Notebook — one-command set-up. Every target installs what it needs itself.
PYTHON ?= python3
VENV   ?= .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
PYTEST_ARGS ?=
# two pytest-xdist workers (each test's real parts bind their own loopback ports and folders)
XDIST ?= -n 2 --dist worksteal
JS_STAMP := tests/js/node_modules/.package-lock.json
PROXY_STAMP := proxy/node_modules/.package-lock.json

# Locked installs (requirements/*.txt, pinned with hashes by `make lock`): every target installs from them.
LOCKS  := requirements/build.txt requirements/dev.txt
PIP_COMPILE := .venv-lock/bin/pip-compile
LOCK_FLAGS := --quiet --generate-hashes --allow-unsafe --strip-extras --no-emit-find-links --no-emit-index-url

.PHONY: demo hub test check lint format bench soak system-deps venv clean ros2 lock test-latest

demo: $(STAMP)  ## convert the sample, start the simulated chair and the Voilà kiosk, print the URL
	$(BIN)/pmk demo

hub: $(STAMP) $(PROXY_STAMP)  ## JupyterHub for a class on this machine: make hub USERS=ana,ben PASSWORD=...
	PMK_HUB_PASSWORD="$(PASSWORD)" $(BIN)/pmk hub --users "$(USERS)" $(HUB_ARGS)

test: $(STAMP) system-deps $(JS_STAMP) $(PROXY_STAMP) ros2 lint  ## install everything the tests need and run the whole suite
	$(BIN)/python -m pytest $(XDIST) $(PYTEST_ARGS)

check: $(STAMP) system-deps $(JS_STAMP) $(PROXY_STAMP) lint  ## the fast loop: lint, then every test but heavy (browser, Voilà, kernels, real stacks) and slow ones
	$(BIN)/python -m pytest -n 2 -m "not heavy and not slow" $(PYTEST_ARGS)

lint: $(STAMP)  ## ruff, and mypy (strict on the pure core: [tool.mypy] in pyproject.toml)
	$(BIN)/ruff check pmk_nb tests bench conftest.py sample_maps requirements
	$(BIN)/ruff format --check pmk_nb tests bench conftest.py sample_maps requirements
	$(BIN)/python -m mypy

bench: $(STAMP) system-deps ros2  ## speed and memory figures, written to bench/results.md
	$(BIN)/pmk bench all

soak: $(STAMP) system-deps  ## 10 kiosk pages for 10 min: nothing may grow; then 10 classroom pages, a chair each (bench/results.md)
	$(BIN)/python bench/soak.py; kiosk=$$?; $(BIN)/python bench/soak_classroom.py && exit $$kiosk

venv: $(STAMP)

format: $(STAMP)  ## ruff's fixes and formatting, in place
	$(BIN)/ruff check --fix pmk_nb tests bench conftest.py sample_maps requirements
	$(BIN)/ruff format pmk_nb tests bench conftest.py sample_maps requirements

# the lock: the build backend first (pmk_nb installs without build isolation), then every dependency
# (runtime, dev, hub) exactly as locked, then pmk_nb itself with no dependency resolution at all
$(STAMP): pyproject.toml $(LOCKS)
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --require-hashes -r requirements/build.txt
	$(BIN)/python -m pip install --quiet --require-hashes --no-deps -r requirements/dev.txt
	$(BIN)/python -m pip install --quiet --no-deps --no-build-isolation -e .
	$(BIN)/python -m pip check
	touch $(STAMP)

# Refresh the locks to the newest releases pyproject.toml's ranges allow (pip-tools in its own venv).
# The base and hub locks are constrained by the dev lock, so every lock names the same versions.
lock:  ## re-resolve requirements/*.txt (pinned, with hashes) to the newest releases
	test -x $(PIP_COMPILE) || { $(PYTHON) -m venv .venv-lock && .venv-lock/bin/python -m pip install --quiet pip-tools==7.7.0; }
	cd requirements && ../$(PIP_COMPILE) $(LOCK_FLAGS) --upgrade --output-file build.txt build.in
	cd requirements && ../$(PIP_COMPILE) $(LOCK_FLAGS) --upgrade --extra dev --extra hub --output-file dev.txt ../pyproject.toml
	cd requirements && ../$(PIP_COMPILE) $(LOCK_FLAGS) --upgrade --output-file base.txt ../pyproject.toml constrain-dev.in
	cd requirements && ../$(PIP_COMPILE) $(LOCK_FLAGS) --upgrade --output-file ros2.txt ros2.in

# The fast tier against the newest releases (a venv of its own, the lock untouched): what moved is
# printed first, so drift is seen before a fresh install meets it.
test-latest: system-deps $(JS_STAMP) $(PROXY_STAMP)  ## the fast tier on the newest releases; prints what moved from the lock
	test -x .venv-latest/bin/python || $(PYTHON) -m venv .venv-latest
	.venv-latest/bin/python -m pip install --quiet --upgrade pip
	.venv-latest/bin/python -m pip install --quiet --upgrade --upgrade-strategy eager -e '.[dev,hub]'
	.venv-latest/bin/python requirements/drift.py
	.venv-latest/bin/python -m pytest -n 2 -m "not heavy and not slow" $(PYTEST_ARGS)

# Real parts the tests use: OpenSSH server (SFTP tests), Debian's Chromium (kiosk tests), espeak-ng
# (spoken feedback for pages without speech synthesis) and Debian's
# ROS 1 (rospy, rosmaster, nav_msgs: the ROS 1 map server and its tests).
system-deps:
	@missing=""; \
	test -x /usr/sbin/sshd || missing="$$missing openssh-server"; \
	test -x /usr/bin/chromium || missing="$$missing chromium"; \
	test -x /usr/bin/espeak-ng || missing="$$missing espeak-ng"; \
	test -x /usr/bin/rosmaster && test -f /usr/share/nav_msgs/msg/MapMetaData.msg \
	  && /usr/bin/python3 -c 'import rospy, genpy, nav_msgs.srv, actionlib_msgs.msg, numpy, yaml, PIL' 2>/dev/null \
	  || missing="$$missing python3-rospy python3-rosmaster python3-nav-msgs python3-geometry-msgs python3-actionlib-msgs python3-genpy ros-nav-msgs python3-numpy python3-yaml python3-pil"; \
	if [ -n "$$missing" ]; then \
	  if [ "$$(id -u)" != 0 ]; then echo "make: need root to install:$$missing (or install them yourself)"; exit 1; fi; \
	  echo "installing Debian packages:$$missing"; \
	  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $$missing >/dev/null; \
	fi

# roslibjs (a second real rosbridge client) checks the simulator; versions fixed by the lock file.
$(JS_STAMP): tests/js/package.json tests/js/package-lock.json
	@command -v npm >/dev/null || { echo "make: the roslibjs tests need Node.js >= 20 and npm"; exit 1; }
	@node -e 'process.exit(+process.versions.node.split(".")[0] >= 20 ? 0 : 1)' || { echo "make: Node.js >= 20 needed, found $$(node --version)"; exit 1; }
	cd tests/js && npm ci --no-audit --no-fund --loglevel=error
	touch $(JS_STAMP)

# JupyterHub's proxy for `pmk hub` (and its test); version fixed by the lock file.
$(PROXY_STAMP): proxy/package.json proxy/package-lock.json
	@command -v npm >/dev/null || { echo "make: pmk hub needs Node.js >= 20 and npm (configurable-http-proxy)"; exit 1; }
	cd proxy && npm ci --no-audit --no-fund --loglevel=error
	touch $(PROXY_STAMP)

clean:
	rm -rf $(VENV) .venv-lock .venv-latest tests/js/node_modules proxy/node_modules .pytest_cache .ruff_cache .mypy_cache .hypothesis test-artifacts .demo

# --- real ROS 2 stack (issue 9) -------------------------------------------------------------
# Jazzy wheels + rosbridge-server-rs + our interfaces (ros/interfaces, rosapi_msgs included so the
# bridge can run rosapi) built with cmake, in a venv outside the checkout ($$PMK_ROS_CACHE, default
# ~/.cache/pmk-ros); instant when nothing changed, one package rebuilt when only it changed (cold on
# 2 cores: about 4-5 min, rosapi_msgs 3 of them). The real-stack test tier (tests/real/)
# and `make bench` use it.
ros2: $(STAMP)
	@command -v cmake >/dev/null && command -v c++ >/dev/null || { echo "make: the ROS 2 interfaces need cmake and a C/C++ compiler"; exit 1; }
	$(BIN)/python -m pmk_nb.robot.wheels
