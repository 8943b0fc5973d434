# Two commands do all set-up on a fresh machine with Python 3.11 and pip:
#   make app    install into .venv and start the main job
#   make test   install into .venv (with the app and test extras) and run the whole test suite
# Both install ".[app,test]": the core package, the web app's packages (panel, bokeh, param) and the
# test tools (pytest, playwright, hypothesis ...); `pip install .` alone gives the core and the CLI.
PYTHON ?= python3
VENV   ?= .venv
BIN     = $(VENV)/bin
STAMP   = $(VENV)/.installed
CHROMIUM ?= /usr/bin/chromium

.PHONY: app test install clean bench browser tutorials-html docs bench-record

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip

$(STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e ".[app,test,docs]"
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

test: $(STAMP) browser
	$(BIN)/python -m pytest
	$(MAKE) docs

# the documentation site: Sphinx with warnings as errors (-W; broken cross-references fail, nitpicky), into
# build/docs/html, then copied to app/docs_site/ so that a wheel built afterwards carries it (served at /docs).
# The tutorials are rendered from the notebooks the test suite executed (test-artifacts/tutorials) when they
# are newer than their source, else executed here in quick mode (docs/_ext/ringlab_docs.py).
DOCS_OUT ?= build/docs
docs: $(STAMP)
	@start=$$(date +%s); \
	$(BIN)/python -m sphinx -W --keep-going -q -j 1 -b html -d $(DOCS_OUT)/doctrees docs $(DOCS_OUT)/html && \
	rm -rf app/docs_site && cp -r $(DOCS_OUT)/html app/docs_site && \
	echo "docs: $(DOCS_OUT)/html (copied to app/docs_site) in $$(( $$(date +%s) - start )) s"

# record the benchmarks the docs' tables are generated from (docs/benchmarks/data/*.json; commit them)
bench-record: $(STAMP)
	$(BIN)/python docs/_ext/bench_record.py hydro
	$(BIN)/python docs/_ext/bench_record.py nbody

bench: $(STAMP)
	$(BIN)/ringcore bench hydro
	$(BIN)/ringcore bench nbody

clean:
	rm -rf $(VENV) build *.egg-info app/docs_site docs/api/generated docs/tutorials/nb docs/benchmarks/generated \
	  docs/teacher/generated
