# The two set-up commands of the README: `make demo` and `make test`.
# Both create the virtual environment in .venv on first use.
PYTHON ?= python3
SHELL := /bin/bash
VENV := .venv
STAMP := $(VENV)/.installed

.PHONY: demo test clean

$(STAMP): pyproject.toml
	@echo "make: setting up $(VENV) (first run only: about 1 minute here, pip's progress follows)"
	@start=$$(date +%s); \
	$(PYTHON) -m venv $(VENV) && \
	$(VENV)/bin/pip install --disable-pip-version-check --progress-bar on --upgrade pip | grep -v "^Requirement already" ; \
	$(VENV)/bin/pip install --disable-pip-version-check --progress-bar on -e ".[test,scale]" | grep -E "^(Collecting|Installing|Successfully|ERROR)" ; \
	status=$${PIPESTATUS[0]}; \
	echo "make: $(VENV) ready in $$(( $$(date +%s) - start )) s"; \
	exit $$status
	@touch $(STAMP)

demo: $(STAMP)
	$(VENV)/bin/broadtrack-graph demo

test: $(STAMP)
	$(VENV)/bin/python -m pytest -q

clean:
	rm -rf $(VENV) build *.egg-info
