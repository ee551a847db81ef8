# tumble — developer entry points. Needs only python3 >= 3.11 and network access to PyPI.
#
#   make reproduce  check every claim of the three papers → out/reproduce/report.html
#   make demo    run every scenario in examples/ (outputs under out/<name>/)
#   make test    the test suite without the slow studies (what CI runs: .ci/run)
#   make bench   the slow studies only (pytest -m slow), with heyoka.py (the bench extra)
#   make lint    ruff (lint and format), mypy and the import-layer contract (CI runs it)
#   make docs    the documentation site → out/docs/index.html (warnings are errors, then the
#                site's checks: no outside resources, no untypeset maths; CI runs it)
#   make docs-check  make docs, then the same pages in headless Chromium: every equation
#                typeset, no request off the site, screenshots in out/docs/_check
#   make clean   remove outputs and caches (keeps .venv; `make distclean` removes it too)

PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin

# Stamp files: the editable install reruns only when pyproject.toml changes
# (or the virtualenv was recreated).
TEST_STAMP := $(VENV)/.installed-test
DEV_STAMP  := $(VENV)/.installed-dev
DOCS_STAMP := $(VENV)/.installed-docs

EXAMPLES := $(wildcard examples/*.toml)

.PHONY: reproduce demo test bench lint docs docs-check clean distclean
.DELETE_ON_ERROR:

$(BIN)/python:
	$(PYTHON) tools/heartbeat.py "creating $(VENV)" -- $(PYTHON) -m venv $(VENV)

# pip says nothing while it installs the wheels it fetched (tens of seconds): tools/heartbeat.py
# says that it is still working, on a terminal.
PIP := $(PYTHON) tools/heartbeat.py "pip is installing" -- $(BIN)/python -m pip

$(TEST_STAMP): pyproject.toml | $(BIN)/python
	$(PIP) install -e ".[test]"
	@echo "tumble is installed in $(VENV): 'source $(BIN)/activate' puts it on your PATH"
	touch $@

$(DEV_STAMP): pyproject.toml $(TEST_STAMP)
	$(PIP) install -e ".[test,dev]"
	touch $@

$(DOCS_STAMP): pyproject.toml $(TEST_STAMP)
	$(PIP) install -e ".[test,docs]"
	touch $@

reproduce: $(TEST_STAMP)
	$(BIN)/tumble reproduce all -o out/reproduce

demo: $(TEST_STAMP)
	@set -e; for f in $(EXAMPLES); do \
		name=$$(basename "$$f" .toml); \
		echo "== $$f -> out/$$name"; \
		$(BIN)/tumble run "$$f" -o "out/$$name"; \
	done

test: $(TEST_STAMP)
	$(BIN)/python -m pytest -m "not slow" -q -n 2 --dist loadfile

bench: $(TEST_STAMP)
	@command -v chromium >/dev/null || { echo "make bench: the report test needs Debian's chromium (apt-get install chromium)"; exit 1; }
	$(PIP) install -e ".[test,bench]"
	$(BIN)/python -m pytest -m slow -q

lint: $(DEV_STAMP)
	$(BIN)/ruff check src tests benchmarks examples tools docs/_ext docs/check_site.py
	$(BIN)/ruff format --check src tests benchmarks examples tools docs/_ext docs/check_site.py
	$(BIN)/mypy src examples/models
	$(BIN)/lint-imports

docs: $(DOCS_STAMP)
	$(BIN)/sphinx-build -W --keep-going -q -b html docs out/docs
	$(BIN)/python docs/check_site.py out/docs

docs-check: docs
	@command -v chromium >/dev/null || { echo "make docs-check: needs Debian's chromium (apt-get install chromium)"; exit 1; }
	$(BIN)/python docs/check_site.py out/docs --browser

clean:
	rm -rf out build dist docs/reference/generated .pytest_cache .hypothesis .mypy_cache .ruff_cache .import_linter_cache
	find . -path ./$(VENV) -prune -o \( -name __pycache__ -o -name '*.egg-info' \) -type d -prune \
		-exec rm -rf {} +

distclean: clean
	rm -rf $(VENV)
