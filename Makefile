# Two commands do all set-up on a fresh machine with Python 3.11 and pip:
#   make app    install into .venv and start the main job
#   make test   install into .venv (with test extras) and run the whole test suite
PYTHON ?= python3
VENV   ?= .venv
BIN     = $(VENV)/bin
STAMP   = $(VENV)/.installed

.PHONY: app test install clean bench

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip

$(STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e ".[test]"
	touch $(STAMP)

install: $(STAMP)

app: $(STAMP)
	$(BIN)/ringcore linear --set tau15 --sigma0 400

test: $(STAMP)
	$(BIN)/python -m pytest

bench: $(STAMP)
	$(BIN)/ringcore bench hydro
	$(BIN)/ringcore bench nbody

clean:
	rm -rf $(VENV) build *.egg-info
