# tools/drivetool/module.mk - drivetool (the link's host tool,
# tools/drivetool/README.md) into the venv: build/venv/bin/drivetool.
# Installed from a copy, so pip's build leaves nothing in the source tree;
# one pip at a time in the venv (after drivekit's), also under -j.
DRIVETOOL      := $(VENV)/bin/drivetool
DRIVETOOL_SRCS := $(wildcard tools/drivetool/pyproject.toml tools/drivetool/drivetool/*.py)
.PHONY: drivetool
drivetool: $(DRIVETOOL) ## build/venv/bin/drivetool: the drive's link tool (tools/drivetool/README.md)
$(DRIVETOOL): $(VENV_STAMP) $(DRIVETOOL_SRCS) | $(DRIVEKIT)
	@rm -rf $(BUILD)/drivetool-src && mkdir -p $(BUILD)/drivetool-src
	@cp -r tools/drivetool/pyproject.toml tools/drivetool/drivetool $(BUILD)/drivetool-src/
	$(VENV)/bin/python -m pip install -q --no-deps $(BUILD)/drivetool-src
	@touch $@
