# One reproducible fit per customer folder, driven by make.
#
#   make fit CUSTOMER=path/to/customer [OUT=path/to/out]
#
# A customer folder holds (see README.md, "Customer folder"):
#   avatar.json         measurement spec (avatar-spec/1) for make-avatar, or
#   poses/              the registered pose meshes (.ply/.obj; a symlink is fine)
#   garment-spec.json   garment spec (garment-spec/1) for make-garment
#   extend.json         optional extension (extend-spec/1) for extend-boundary
#   motion.json         motion spec (motion/1) for simulate-adapt
#   seams.json          optional seam spec (seam-spec/1) for export-rest
#   customer.mk         optional overrides of the *_FLAGS variables below
#
# The last stage, fit-report, writes $(OUT)/report/index.html: pictures, 3D
# views and the figures of every stage (NO_ADAPT=1 adds the design simulated
# without adaptation, shown beside the adapted garment).
#
# Every stage writes one folder under $(OUT) and its report.json last, so a
# stage's report is the make target that marks it done; make reruns exactly
# the stages whose inputs, flags (customer.mk or the command line) or binary
# changed, and those after them. Stages write to a
# temporary folder and rename it into place, so a failed stage leaves the
# previous result (or nothing) and the earlier stages' outputs intact.

ifndef CUSTOMER
$(error CUSTOMER=path/to/customer-folder is required)
endif
C   := $(patsubst %/,%,$(CUSTOMER))
OUT ?= $(C)/out
BIN ?= build/bin

AVATAR_FLAGS   ?=
REGISTER_FLAGS ?=
GARMENT_FLAGS  ?=
SIMULATE_FLAGS ?=
EXPORT_FLAGS   ?=
# NO_SEW_CHECK=1: export-rest skips the sewn-fit check (the garment sewn from
# the flat pieces simulated through every key pose of the fit, judged like the
# fit's verification). On by default: it costs about one verification run.
NO_SEW_CHECK   ?=
# NO_ADAPT=1: also simulate the garment as designed through the same motion
# without adaptation (fit-noadapt/), so that the report shows the design and
# the adapted garment side by side. Off by default: it doubles the simulation.
NO_ADAPT       ?=
REPORT_FLAGS   ?=
# FABRIC_WIDTH=<metres>: make-marker nests the pattern's pieces on a roll of
# that width (marker/: marker.svg, marker.pdf, its length and utilisation),
# and the report shows it. Set in customer.mk, or by the garment spec's
# "fabric_width" (metres); off when neither names one.
FABRIC_WIDTH   ?=
MARKER_FLAGS   ?=
# OPEN_POSE=<pose> OPEN_TOWARD=<other pose> OPEN_STEPS=<n>: fit the garment
# to the body one n-th of the way from <pose> to <other pose> (interp-poses)
# in place of the captured <pose>, the other poses as captured. For a capture
# in which two body parts nearly touch where the garment has to pass between
# them (a hand resting on the thigh over a skirt): cloth the body holds
# cannot be fitted.
OPEN_POSE      ?=
OPEN_TOWARD    ?=
OPEN_STEPS     ?= 20
-include $(C)/customer.mk
# AUTO_OPEN=1 (the default): when simulate-adapt stops at a key pose that the
# body holds (report.json's "held", exit 8) and proposes the least opening of
# it that frees the cloth, the fit is made again with that pose opened, as
# OPEN_POSE would (an explicit OPEN_POSE always wins). The held run's report
# is kept in $(OUT)/fit-held/ with the body that held it (body_<pose>.ply),
# the choice in $(OUT)/auto-open.mk, which the next make fit starts from
# (delete it to decide again). AUTO_OPEN=0: the captured poses only.
AUTO_OPEN ?= 1
PYTHON ?= /usr/bin/python3
ifeq ($(OPEN_POSE),)
ifneq ($(AUTO_OPEN),0)
AUTO_OPENING := 1
-include $(OUT)/auto-open.mk
endif
endif
ifeq ($(FABRIC_WIDTH),)
FABRIC_WIDTH := $(shell sed -n 's/.*"fabric_width" *: *\([0-9.eE+-]*\).*/\1/p' '$(C)/garment-spec.json' 2>/dev/null | head -n 1)
endif

# Stages print only errors, except simulate-adapt, which runs for minutes and
# prints its progress (a live line on a terminal, a line every 10 s in a log)
# and each key pose's figures.
QUIET   ?= --quiet
SIMULATE_QUIET ?=
# BLAS/solver threads of every stage but simulate-adapt, which keeps its own
# default of one (BLAS threads cost more than they save on its matrices), and
# the worker threads of simulate-adapt and fit-report (views rendered in
# parallel; the pictures are the same for any count). Its own --workers default is 2 where the
# machine has two cores (a second thread prepares the body frames and
# adaptations; the outputs are the same for any count), but make fit gives it
# THREADS:
# on the shared 2-core build machine under load (load average 7-12) two
# threads were slower, not faster: wall time x1.26 and x1.46 against one
# thread (small-shirt fit, median of 5 runs interleaved; README.md). On a
# machine of its own, SIMULATE_WORKERS=2 gains the 1.2-1.3x of BENCHMARKS.md.
THREADS ?= 1
SIMULATE_WORKERS ?= $(THREADS)
RUN = @echo "fit: $(1)"; $(BIN)/$(1) --threads $(THREADS)
RUN_SIMULATE = @echo "fit: simulate-adapt"; $(BIN)/simulate-adapt --workers $(SIMULATE_WORKERS)

# Each stage's effective flags are a prerequisite: $(OUT)/flags/<stage> holds
# them and is rewritten (at parse time) only when they differ, so changing
# customer.mk or a *_FLAGS variable reruns exactly that stage and the ones
# after it, and a rerun with the same flags does nothing. Thread counts are
# left out: they do not change any output.
FLAGS_DIR := $(OUT)/flags
quote = '$(subst ','\'',$(1))'
define flags_stamp
$(shell mkdir -p '$(FLAGS_DIR)' && printf '%s\n' $(call quote,$(strip $(2))) | cmp -s - '$(FLAGS_DIR)/$(1)' || printf '%s\n' $(call quote,$(strip $(2))) > '$(FLAGS_DIR)/$(1)')$(FLAGS_DIR)/$(1)
endef
AVATAR_STAMP   := $(call flags_stamp,make-avatar,$(AVATAR_FLAGS))
# An opened pose is part of what register-check registers: setting or
# dropping OPEN_POSE reruns it and everything after it.
REGISTER_STAMP := $(call flags_stamp,register-check,$(REGISTER_FLAGS) $(if $(OPEN_POSE),open-pose $(OPEN_POSE) $(OPEN_TOWARD) $(OPEN_STEPS)))
GARMENT_STAMP  := $(call flags_stamp,make-garment,$(GARMENT_FLAGS))
SIMULATE_STAMP := $(call flags_stamp,simulate-adapt,$(SIMULATE_FLAGS))
EXPORT_STAMP   := $(call flags_stamp,export-rest,$(EXPORT_FLAGS) $(if $(NO_SEW_CHECK),no-sew-check))
REPORT_STAMP   := $(call flags_stamp,fit-report,$(REPORT_FLAGS) $(if $(NO_ADAPT),no-adapt) $(if $(FABRIC_WIDTH),marker))
MARKER_STAMP   := $(call flags_stamp,make-marker,$(FABRIC_WIDTH) $(MARKER_FLAGS))

# --- body -------------------------------------------------------------------
ifneq ($(wildcard $(C)/avatar.json),)
BODY_DIR   := $(OUT)/body
POSE_FILES := $(OUT)/body/report.json
$(OUT)/body/report.json: $(C)/avatar.json $(AVATAR_STAMP) $(BIN)/make-avatar
	$(call RUN,make-avatar) $< $(AVATAR_FLAGS) --out $(@D) --force $(QUIET)
POSE_INPUT := $(OUT)/body
else
POSE_INPUT := $(C)/poses
POSE_FILES := $(sort $(wildcard $(C)/poses/*.ply $(C)/poses/*.obj))
endif

ifneq ($(OPEN_POSE),)
ifeq ($(OPEN_TOWARD),)
$(error OPEN_POSE=$(OPEN_POSE) needs OPEN_TOWARD, the pose to open it towards)
endif
# The other poses are linked and the opened one written in its place, under
# its own name, so that the motion and the garment spec name it as before.
OPEN_STAMP := $(call flags_stamp,open-pose,$(OPEN_POSE) $(OPEN_TOWARD) $(OPEN_STEPS))
CAPTURED_POSES := $(POSE_INPUT)
$(OUT)/opened/report.json: $(POSE_FILES) $(OPEN_STAMP) $(BIN)/interp-poses
	@echo "fit: interp-poses"
	@rm -rf '$(OUT)/opened.tmp' && mkdir -p '$(OUT)/opened.tmp/poses'
	@printf '{"schema": "motion/1", "steps": %s, "sequence": ["%s", "%s"]}\n' \
	  '$(OPEN_STEPS)' '$(OPEN_POSE)' '$(OPEN_TOWARD)' > '$(OUT)/opened.tmp/motion.json'
	@poses=$$(ls -d '$(abspath $(CAPTURED_POSES))'/*.ply '$(abspath $(CAPTURED_POSES))'/*.obj 2>/dev/null); \
	$(BIN)/interp-poses $$poses --motion '$(OUT)/opened.tmp/motion.json' --frames 1 --no-compare \
	  --threads $(THREADS) --out '$(OUT)/opened.tmp/frame' $(QUIET) || { rm -rf '$(OUT)/opened.tmp'; exit 4; }; \
	for f in $$poses; do \
	  case "$$(basename "$$f")" in $(OPEN_POSE).ply|$(OPEN_POSE).obj) ;; *) ln -s "$$f" '$(OUT)/opened.tmp/poses/' ;; esac; \
	done
	@mv '$(OUT)/opened.tmp/frame/frame_00001.ply' '$(OUT)/opened.tmp/poses/$(OPEN_POSE).ply'
	@mv '$(OUT)/opened.tmp/frame/report.json' '$(OUT)/opened.tmp/report.json'
	@rm -rf '$(OUT)/opened.tmp/frame' '$(OUT)/opened' && mv '$(OUT)/opened.tmp' '$(OUT)/opened'
POSE_INPUT := $(OUT)/opened/poses
POSE_FILES := $(OUT)/opened/report.json
endif

$(OUT)/poses/report.json: $(POSE_FILES) $(REGISTER_STAMP) $(BIN)/register-check
	$(call RUN,register-check) $(POSE_INPUT) $(REGISTER_FLAGS) --out $(@D) --force $(QUIET)

# --- garment ----------------------------------------------------------------
$(OUT)/garment/report.json: $(C)/garment-spec.json $(OUT)/poses/report.json $(GARMENT_STAMP) $(BIN)/make-garment
	$(call RUN,make-garment) $< --poses $(OUT)/poses/poses.json $(GARMENT_FLAGS) --out $(@D) --force $(QUIET)

ifneq ($(wildcard $(C)/extend.json),)
GARMENT := $(OUT)/extended/garment.json
$(OUT)/extended/report.json: $(OUT)/garment/report.json $(C)/extend.json $(OUT)/poses/report.json $(BIN)/extend-boundary
	$(call RUN,extend-boundary) $(OUT)/garment/garment.json $(C)/extend.json --body $(OUT)/poses/poses.json --out $(@D) --force $(QUIET)
GARMENT_REPORT := $(OUT)/extended/report.json
else
GARMENT := $(OUT)/garment/garment.json
GARMENT_REPORT := $(OUT)/garment/report.json
endif

# --- simulation and adaptation -------------------------------------------------
# simulate-adapt exits 8 when its verification fails (the final rest shape,
# simulated afresh, stretches above the limit somewhere); its outputs are
# complete, so the pattern and the report are still made, and `fit` exits 8
# at the end, naming the report that shows where.
VERDICT_OK = || test $$? -eq 8
$(OUT)/fit/report.json: $(GARMENT_REPORT) $(C)/motion.json $(OUT)/poses/report.json $(SIMULATE_STAMP) $(BIN)/simulate-adapt
	$(RUN_SIMULATE) --poses $(OUT)/poses/poses.json --motion $(C)/motion.json \
	  --garment $(GARMENT) $(SIMULATE_FLAGS) --out $(@D) --force $(SIMULATE_QUIET) $(VERDICT_OK)
ifeq ($(AUTO_OPENING)$(OPEN_POSE),1)
	@open=$$($(PYTHON) -c 'import json, sys; h = json.load(open(sys.argv[1])).get("held"); o = h and h.get("open_suggestion"); \
	  print("%s %s %d %.0f %.0f" % (o["pose"], o["toward"], o["steps"], o["largest_body_displacement_mm"], o["smallest_gap_mm"] or 0) if o else "")' $@) || exit 1; \
	if [ -n "$$open" ]; then \
	  set -- $$open; \
	  echo "fit: the body holds the cloth at $$1: fitting it opened 1/$$3 towards $$2 (the body moves $$4 mm at most; at least $$5 mm of room where it held; AUTO_OPEN=0 turns this off)"; \
	  rm -rf '$(OUT)/fit-held' && cp -r '$(@D)' '$(OUT)/fit-held' && cp '$(OUT)/poses/'"$$1"'.ply' "$(OUT)/fit-held/body_$$1.ply"; \
	  printf 'OPEN_POSE := %s\nOPEN_TOWARD := %s\nOPEN_STEPS := %s\n' "$$1" "$$2" "$$3" > '$(OUT)/auto-open.mk'; \
	  $(MAKE) --no-print-directory -f $(firstword $(MAKEFILE_LIST)) '$@'; \
	fi
endif

ifneq ($(NO_ADAPT),)
NO_ADAPT_REPORT := $(OUT)/fit-noadapt/report.json
$(NO_ADAPT_REPORT): $(GARMENT_REPORT) $(C)/motion.json $(OUT)/poses/report.json $(SIMULATE_STAMP) $(BIN)/simulate-adapt
	$(RUN_SIMULATE) --no-adapt --poses $(OUT)/poses/poses.json --motion $(C)/motion.json \
	  --garment $(GARMENT) $(SIMULATE_FLAGS) --out $(@D) --force $(SIMULATE_QUIET) $(VERDICT_OK)
endif

# --- pattern -------------------------------------------------------------------
# export-rest exits 8 when the garment sewn from its pieces fails a key pose
# of the fit (sewn-fit check); its outputs are complete, so the report is
# still made and `fit` exits 8 at the end, as for simulate-adapt's verdict.
# It simulates for about as long as the fit's verification, so it prints its
# progress like simulate-adapt.
SEAMS := $(wildcard $(C)/seams.json)
$(OUT)/pattern/report.json: $(OUT)/fit/report.json $(SEAMS) $(EXPORT_STAMP) $(BIN)/export-rest
	$(call RUN,export-rest) $(OUT)/fit/rest.ply --garment $(GARMENT) $(if $(SEAMS),--seams $(SEAMS) --body $(OUT)/poses/poses.json) \
	  $(if $(NO_SEW_CHECK),,--fit $(OUT)/fit/report.json) $(EXPORT_FLAGS) --out $(@D) --force $(SIMULATE_QUIET) $(VERDICT_OK)

# --- marker --------------------------------------------------------------------
# The pieces nested on the customer's fabric width: how much fabric to buy.
ifneq ($(FABRIC_WIDTH),)
MARKER_REPORT := $(OUT)/marker/report.json
$(MARKER_REPORT): $(OUT)/pattern/report.json $(MARKER_STAMP) $(BIN)/make-marker
	$(call RUN,make-marker) $(OUT)/pattern --width $(FABRIC_WIDTH) --title $(notdir $(C)) $(MARKER_FLAGS) --out $(@D) --force $(QUIET)
endif

# --- report --------------------------------------------------------------------
# Pictures, 3D views and every stage's figures in one folder that opens from disk.
$(OUT)/report/report.json: $(OUT)/pattern/report.json $(OUT)/fit/report.json $(NO_ADAPT_REPORT) $(MARKER_REPORT) $(REPORT_STAMP) $(BIN)/fit-report
	$(call RUN,fit-report) $(OUT) $(REPORT_FLAGS) --workers $(THREADS) --out $(@D) --force $(QUIET)

.PHONY: fit
.DEFAULT_GOAL := fit
fit: $(OUT)/report/report.json
	@echo "fit: done: rest shape $(OUT)/fit/rest.ply, pattern $(OUT)/pattern/pattern.svg, reports $(OUT)/*/report.json"
	@echo "fit: report: $(OUT)/report/index.html"
	@status=0; \
	if grep -q '"verdict": *"fail"' $(OUT)/fit/report.json; then \
	  echo "fit: error[check]: the fitted garment fails its verification (see $(OUT)/report/index.html)" >&2; status=8; fi; \
	if grep -q '"verdict": *"fail"' $(OUT)/pattern/report.json; then \
	  echo "fit: error[check]: the garment sewn from the pattern fails its fit (see $(OUT)/pattern/report.json, /sewn_fit)" >&2; status=8; fi; \
	exit $$status
