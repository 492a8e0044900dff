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

.PHONY: demo hub test check lint bench soak system-deps venv clean ros2

demo: $(STAMP)  ## convert the sample, start the simulated chair and the Voilà kiosk, print the URL
	$(BIN)/pmk demo

hub: $(STAMP) $(PROXY_STAMP)  ## JupyterHub for a class on this machine: make hub USERS=ana,ben PASSWORD=...
	PMK_HUB_PASSWORD="$(PASSWORD)" $(BIN)/pmk hub --users "$(USERS)"

test: $(STAMP) system-deps $(JS_STAMP) $(PROXY_STAMP) ros2 lint  ## install everything the tests need and run the whole suite
	$(BIN)/python -m pytest $(XDIST) $(PYTEST_ARGS)

check: $(STAMP) system-deps $(JS_STAMP) $(PROXY_STAMP) lint  ## the fast loop: lint, then every test but heavy (browser, Voilà, kernels, real stacks) and slow ones
	$(BIN)/python -m pytest -n 2 -m "not heavy and not slow" $(PYTEST_ARGS)

lint: $(STAMP)  ## ruff, and mypy (strict on the pure core: [tool.mypy] in pyproject.toml)
	$(BIN)/ruff check pmk_nb tests bench conftest.py sample_maps
	$(BIN)/ruff format --check pmk_nb tests bench conftest.py sample_maps
	$(BIN)/python -m mypy

bench: $(STAMP) system-deps ros2  ## speed and memory figures, written to bench/results.md
	$(BIN)/pmk bench all

soak: $(STAMP) system-deps  ## 10 kiosk pages for 10 min: nothing may grow; then 10 classroom pages, a chair each (bench/results.md)
	$(BIN)/python bench/soak.py; kiosk=$$?; $(BIN)/python bench/soak_classroom.py && exit $$kiosk

venv: $(STAMP)

$(STAMP): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[dev,hub]'
	touch $(STAMP)

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
	rm -rf $(VENV) tests/js/node_modules proxy/node_modules .pytest_cache .ruff_cache .mypy_cache .hypothesis test-artifacts .demo

# --- real ROS 2 stack (issue 9) -------------------------------------------------------------
# Jazzy wheels + rosbridge-server-rs + our interfaces (ros/interfaces, rosapi_msgs included so the
# bridge can run rosapi) built with cmake, in a venv outside the checkout ($$PMK_ROS_CACHE, default
# ~/.cache/pmk-ros); instant when nothing changed, one package rebuilt when only it changed (cold on
# 2 cores: about 4-5 min, rosapi_msgs 3 of them). The real-stack test tier (tests/real/)
# and `make bench` use it.
ros2: $(STAMP)
	@command -v cmake >/dev/null && command -v c++ >/dev/null || { echo "make: the ROS 2 interfaces need cmake and a C/C++ compiler"; exit 1; }
	$(BIN)/python -m pmk_nb.robot.wheels
