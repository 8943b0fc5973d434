# Two commands do all set-up on a fresh machine with Python 3.11 and pip:
#   make app    install into .venv and start the main job
#   make test   install into .venv (with the app and test extras) and run the whole test suite
# Both install ".[app,test]": the core package, the web app's packages (panel, bokeh, param) and the
# test tools (pytest, pytest-xdist, import-linter, playwright, hypothesis ...); `pip install .` alone gives
# the core and the CLI.  `make test-fast` runs the core and headless-app tiers only (a developer's check).
PYTHON ?= python3
VENV   ?= .venv
BIN     = $(VENV)/bin
STAMP   = $(VENV)/.installed
CHROMIUM ?= /usr/bin/chromium

.PHONY: app test test-fast lint-imports install clean bench browser tutorials-html

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip

$(STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e ".[app,test]"
	touch $(STAMP)

install: $(STAMP)

# Debian's Chromium for the real-browser test (Playwright's own browser download does not work here)
browser:
	@test -x $(CHROMIUM) || { command -v apt-get >/dev/null && \
	  (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null) || \
	  echo "warning: could not install chromium; browser tests will be skipped"; }

PORT ?= 5006
TUTORIALS_HTML ?= build/tutorials-html
app: $(STAMP)
	@echo "ringlab app: open http://localhost:$(PORT)/main  (Ctrl-C stops the server)"
	@test -f $(TUTORIALS_HTML)/index.html || echo "note: no executed tutorials in $(TUTORIALS_HTML) ('make tutorials-html' adds the app's links to them)"
	@mkdir -p $(TUTORIALS_HTML)
	RINGLAB_TUTORIALS_HTML=$(TUTORIALS_HTML) $(BIN)/python -m panel serve app/main.py --warm --port $(PORT) \
	  --static-dirs tutorials=$(TUTORIALS_HTML)

# the tutorials executed (quick mode) as offline HTML pages, served by `make app` at /tutorials/ and linked
# from the tabs and lessons; reuses notebooks the test suite executed (test-artifacts/tutorials) if up to date
tutorials-html: $(STAMP)
	$(BIN)/python scripts/tutorials_html.py --out $(TUTORIALS_HTML) --from test-artifacts/tutorials

# tests in tiers (tests/core, tests/app, tests/browser, tests/notebooks) on pytest-xdist workers; --dist loadgroup
# keeps the browser tests in one worker (one app server and one Chromium at a time: tests/conftest.py)
PYTEST_WORKERS ?= 2
PYTEST_XDIST = -n $(PYTEST_WORKERS) --dist loadgroup

# the app's layers and "ringcore imports no web stack" (contracts in pyproject.toml)
lint-imports: $(STAMP)
	$(BIN)/lint-imports --no-cache

test: $(STAMP) browser lint-imports
	$(BIN)/python -m pytest $(PYTEST_XDIST)

test-fast: $(STAMP) lint-imports
	$(BIN)/python -m pytest $(PYTEST_XDIST) -m "not slow" tests/core tests/app

bench: $(STAMP)
	$(BIN)/ringcore bench hydro
	$(BIN)/ringcore bench nbody

clean:
	rm -rf $(VENV) build *.egg-info
