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

.PHONY: app test test-fast test-newest slow-list lint-imports install clean bench browser udunits tutorials-html docs docs-site bench-record wheel

# The venv gets uv (https://docs.astral.sh/uv/), which installs the same releases as pip in a fraction of the time
# (measured on the 2-core machine: 32 s against 116 s for ".[app,test,docs]", bytecode compiled by both, as
# pip does: without it every process of the suite imported its packages from source, 2-3x slower where
# PYTHONDONTWRITEBYTECODE is set); where uv cannot be installed or cannot reach the package index (it does not
# read pip.conf), pip installs instead.
$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q uv || echo "note: uv not available; installing with pip (slower)"

define pip_install
	@if test -x $(BIN)/uv && $(BIN)/uv pip install -q --compile-bytecode --python $(BIN)/python $(1); then :; else \
	  echo "installing with pip"; $(BIN)/python -m pip install -q $(1); fi
endef

# (the requirements in variables: a comma inside $(call ...) would split its arguments)
REQ_ALL = -e ".[app,test,docs]"
REQ_APP = -e ".[app]"
REQ_APP_DOCS = -e ".[app,viz,docs]"
$(STAMP): pyproject.toml setup.py | $(BIN)/python
	$(call pip_install,$(REQ_ALL))
	touch $(STAMP)

install: $(STAMP)

# Debian's Chromium for the real-browser test (Playwright's own browser download does not work here)
browser:
	@test -x $(CHROMIUM) || { command -v apt-get >/dev/null && \
	  (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null) || \
	  echo "warning: could not install chromium; browser tests will be skipped"; }

# UDUNITS-2 for cfchecks (the test of the files' CF conventions, tests/core/test_cf_files.py): Debian's library
udunits:
	@test -f /usr/share/xml/udunits/udunits2.xml || { command -v apt-get >/dev/null && \
	  (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libudunits2-0 udunits-bin >/dev/null) || \
	  echo "warning: could not install udunits2; the CF test of the written files will fail"; }

# `make app` installs what the app and its documentation site need (".[app,viz,docs]") and starts the lab with
# `ringlab serve`; the documentation site in $(DOCS_SITE) is served at /docs and the app's tutorial links point to
# /docs/tutorials/<name>.html.  Without a site, the site is built once in the background (niced; its log in
# build/docs-app.log, the build's PID in $(DOCS_SITE).building) while the lab already runs: the server serves it
# at /docs as soon as it is there, no restart (pages opened before show "being built").
PORT ?= 5006
DOCS_SITE ?= app/docs_site
APP_STAMP = $(VENV)/.installed-app
$(APP_STAMP): pyproject.toml setup.py | $(BIN)/python
	$(call pip_install,$(REQ_APP_DOCS))
	touch $(APP_STAMP)

app: $(APP_STAMP)
	@test -f $(DOCS_SITE)/index.html || { mkdir -p build; \
	  echo "no documentation site in $(DOCS_SITE): building it in the background (log: build/docs-app.log); the lab serves it at /docs when done"; \
	  nice -n 19 $(MAKE) --no-print-directory docs-site DOCS_COPY=$(DOCS_SITE) > build/docs-app.log 2>&1 & \
	  echo $$! > $(DOCS_SITE).building; }
	RINGLAB_DOCS_DIR=$(DOCS_SITE) $(BIN)/ringlab serve --port $(PORT)

# the tutorials executed (quick mode) as offline HTML pages in $(DOCS_SITE)/tutorials/nb, when the full
# documentation site is not built; reuses notebooks the test suite executed (test-artifacts/tutorials) if up to date
tutorials-html: $(STAMP)
	$(BIN)/python scripts/tutorials_html.py --out $(DOCS_SITE)/tutorials/nb --from test-artifacts/tutorials

# tests in tiers (tests/core, tests/app, tests/browser, tests/notebooks) on pytest-xdist workers; --dist loadgroup
# keeps the browser tests in one worker (one app server and one Chromium at a time: tests/conftest.py)
PYTEST_WORKERS ?= 2
PYTEST_XDIST = -n $(PYTEST_WORKERS) --dist loadgroup

# the app's layers and "ringcore imports no web stack" (contracts in pyproject.toml)
lint-imports: $(STAMP)
	$(BIN)/lint-imports --no-cache

# `make test-newest` and then the install tier run while `make docs` builds (Sphinx runs on one core, these on the
# other: test-newest reuses its venv when present, ~2.5 min here; the install tier installs the fresh venv's
# packages first and waits for the docs build (RINGLAB_DOCS_PID) before it builds the wheel with the site inside)
test: $(STAMP) browser udunits lint-imports
	$(BIN)/python -m pytest $(PYTEST_XDIST) --ignore=tests/install
	@$(MAKE) docs & docs_pid=$$!; \
	$(MAKE) --no-print-directory test-newest; newest_rc=$$?; \
	RINGLAB_DOCS_PID=$$docs_pid $(BIN)/python -m pytest tests/install; rc=$$?; \
	wait $$docs_pid || { echo "make docs failed"; exit 1; }; \
	test $$newest_rc -eq 0 || { echo "make test-newest failed"; exit 1; }; exit $$rc

# the developer's check: the core and app tiers without the `slow` tests (marked in their files, or listed in
# tests/slow_tests.txt: 2 s or more each here; `make slow-list` re-measures and updates the list)
test-fast: $(STAMP) udunits lint-imports
	$(BIN)/python -m pytest $(PYTEST_XDIST) -m "not slow" tests/core tests/app

# the app on the newest Panel and Bokeh releases (the pins are lower bounds): a venv of its own (made once, reused
# while pyproject.toml and setup.py are older than it) with them upgraded to the newest releases on the index
# (--refresh-package: not an index page uv cached earlier; scripts/newest_versions.py prints the versions before and
# after and fails unless they are the index's newest), then the headless tests of the app's websocket handler, its
# web cases and the public-API scan, and two browser tests (one at a time).  The replacements of library code
# (fast_defaults, fast_patch, joining) install only over the source they were written for: on a newer release the
# app runs on the library's own code
NEWEST_VENV ?= .venv-newest
NEWEST_PACKAGES ?= panel bokeh
NEWEST_TESTS ?= tests/app/test_socket_guard.py tests/app/test_web_cases.py tests/app/test_public_api_only.py
NEWEST_BROWSER ?= tests/browser/test_browser.py tests/browser/test_browser_reload.py
test-newest: browser
	@start=$$(date +%s); \
	$(MAKE) --no-print-directory $(NEWEST_VENV)/.installed VENV=$(NEWEST_VENV) || exit 1; \
	$(NEWEST_VENV)/bin/python scripts/newest_versions.py --before $(NEWEST_PACKAGES); \
	if test -x $(NEWEST_VENV)/bin/uv; then \
	  $(NEWEST_VENV)/bin/uv pip install -q --upgrade $(addprefix --refresh-package ,$(NEWEST_PACKAGES)) \
	    --python $(NEWEST_VENV)/bin/python $(NEWEST_PACKAGES) || exit 1; \
	else $(NEWEST_VENV)/bin/python -m pip install -q --upgrade $(NEWEST_PACKAGES) || exit 1; fi; \
	$(NEWEST_VENV)/bin/python scripts/newest_versions.py --check $(NEWEST_PACKAGES) || exit 1; \
	$(NEWEST_VENV)/bin/python -m pytest -p no:xdist $(NEWEST_TESTS) || exit 1; \
	for t in $(NEWEST_BROWSER); do $(NEWEST_VENV)/bin/python -m pytest -p no:xdist $$t || exit 1; done; \
	echo "test-newest: passed in $$(( $$(date +%s) - start )) s"

slow-list: $(STAMP)
	$(BIN)/python tests/slow_list.py


# the documentation site: Sphinx with warnings as errors (-W; broken cross-references fail, nitpicky), into
# build/docs/html, then copied to app/docs_site/ so that a wheel built afterwards carries it (served at /docs).
# The tutorials are rendered from the notebooks the test suite executed (test-artifacts/tutorials) when they
# are newer than their source, else executed here in quick mode (docs/_ext/ringlab_docs.py).
DOCS_OUT ?= build/docs
DOCS_COPY ?= app/docs_site
docs: $(STAMP)
	@$(MAKE) --no-print-directory docs-site

# the Sphinx build alone (what `docs` runs once the venv is complete; `make app` runs it in the background):
# the copy is swapped in whole, so a server never sees a half-copied site
docs-site:
	@start=$$(date +%s); \
	$(BIN)/python -m sphinx -W --keep-going -q -j 1 -b html -d $(DOCS_OUT)/doctrees docs $(DOCS_OUT)/html && \
	rm -rf $(DOCS_COPY).new && cp -r $(DOCS_OUT)/html $(DOCS_COPY).new && rm -rf $(DOCS_COPY) && \
	mv $(DOCS_COPY).new $(DOCS_COPY) && rm -f $(DOCS_COPY).building && \
	echo "docs: $(DOCS_OUT)/html (copied to $(DOCS_COPY)) in $$(( $$(date +%s) - start )) s"

# a wheel with the documentation site inside (dist/); a wheel built without the site (pip wheel ., uv build on a
# checkout without `make docs`) has "nodocs" in its version (setup.py), so the two can never be confused
wheel: docs
	rm -rf dist && $(BIN)/python -m pip wheel --no-deps -q -w dist . && ls dist/*.whl

# record the benchmarks the docs' tables are generated from (docs/benchmarks/data/*.json; commit them)
bench-record: $(STAMP)
	$(BIN)/python docs/_ext/bench_record.py hydro
	$(BIN)/python docs/_ext/bench_record.py nbody

bench: $(STAMP)
	$(BIN)/ringcore bench hydro
	$(BIN)/ringcore bench nbody

clean:
	rm -rf $(VENV) build *.egg-info app/docs_site app/docs_site.new app/docs_site.building docs/api/generated docs/tutorials/nb docs/benchmarks/generated \
	  docs/teacher/generated
