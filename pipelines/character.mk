# capture folder → aligned database → part models → motion spaces → transitions → character.glb
# → previews, every step a file target (docs/pipelines.md).
#
#   make -f pipelines/character.mk CAPTURE=capture GRAPH=configs/graphs/tiny.json OUT=out -j 4
#
# Variables (defaults below): CAPTURE, GRAPH (required); OUT, PARTS, DATABASE (aligned: the
# stages after alignment read OUT/aligned/database.json; truth: the capture's ground-truth
# database, for synthetic captures), BLOCKS (similarity row blocks), REGISTER_JOBS (registration
# jobs: 1 = one step; K > 1 = a trunk job, K shard jobs and a merge), THREADS (per step),
# SUBMIT (command prefix of the heavy steps, e.g. `srun -c 2`), CONTROL (playback script), NAME,
# BIN (the surfcap executables), TRACK_TOOLS (yes: a rebuilt executable redoes its steps),
# LOG_LEVEL and <STAGE>_OPTIONS (extra options per tool), THREE (where scripts/vendor_three.sh
# puts the three.js package the report's viewer inlines).
#
# Targets: all (default: character + previews), alignment, similarity, parts, spaces, graph,
# transitions, character, previews, summary, report (OUT/report/index.html: every figure,
# the previews and a 3D viewer in one self-contained page), clean, tidy.
#
# Every step writes through temporary names and renames (docs/cli.md "Outputs"); a step that
# fails or is killed has its targets removed (.DELETE_ON_ERROR), so the next make redoes it, and
# a step starts by removing what a killed run of it left (its own directory or temporary files).

SURFCAP := $(abspath $(dir $(lastword $(MAKEFILE_LIST)))..)
PLAN := python3 $(SURFCAP)/pipelines/plan.py

CAPTURE ?=
GRAPH ?=
OUT ?= out/character
PARTS ?= $(SURFCAP)/configs/parts/human6.json
DATABASE ?= aligned
BLOCKS ?= 4
REGISTER_JOBS ?= 1
THREADS ?= 0
SUBMIT ?=
NAME ?= character
CONTROL ?= $(SURFCAP)/configs/control/$(basename $(notdir $(GRAPH)))_timeline.json
BIN ?= $(SURFCAP)/build/tools
TRACK_TOOLS ?= yes
LOG_LEVEL ?= warn
HISTOGRAMS_OPTIONS ?=
SIMILARITY_OPTIONS ?=
TREE_OPTIONS ?=
REGISTER_OPTIONS ?=
LEARN_OPTIONS ?=
SPACES_OPTIONS ?=
TRANSITIONS_OPTIONS ?=
EXPORT_OPTIONS ?=
PLAY_OPTIONS ?=
THREE ?= $(SURFCAP)/build/cache/three

ifeq ($(strip $(OUT)),)
$(error character.mk: OUT must not be empty)
endif
# summary, report, tidy and clean need only OUT; every other goal reads the inputs.
INPUTS_NEEDED := $(if $(MAKECMDGOALS),$(filter-out summary report tidy clean,$(MAKECMDGOALS)),all)
ifneq ($(INPUTS_NEEDED),)
ifeq ($(strip $(CAPTURE)),)
$(error character.mk: set CAPTURE=<capture folder> (see docs/pipelines.md))
endif
ifeq ($(strip $(GRAPH)),)
$(error character.mk: set GRAPH=<graph config>, e.g. $(SURFCAP)/configs/graphs/tiny.json)
endif
ifeq ($(wildcard $(CAPTURE)/capture.json),)
$(error character.mk: $(CAPTURE)/capture.json does not exist)
endif
ifeq ($(filter $(DATABASE),aligned truth),)
$(error character.mk: DATABASE must be aligned or truth, not '$(DATABASE)')
endif
ifneq ($(shell echo '$(REGISTER_JOBS)' | grep -xE '[1-9][0-9]{0,4}'),$(REGISTER_JOBS))
$(error character.mk: REGISTER_JOBS must be a positive integer, not '$(REGISTER_JOBS)')
endif
endif

.DELETE_ON_ERROR:
.SUFFIXES:
.SECONDEXPANSION:

# What the inputs say (read once, when make starts).
ifneq ($(INPUTS_NEEDED),)
plan = $(or $(shell $(PLAN) $(1) || echo PLAN-FAILED),PLAN-EMPTY)
SEQUENCES := $(call plan,sequences $(CAPTURE))
ROW_BLOCKS := $(subst :,-,$(call plan,blocks $(CAPTURE) $(BLOCKS)))
SPACES := $(call plan,spaces $(GRAPH))
EDGES := $(call plan,edges $(GRAPH))
CAPTURE_FILES := $(call plan,files $(CAPTURE))
ifneq ($(filter PLAN-FAILED PLAN-EMPTY,$(SEQUENCES) $(ROW_BLOCKS) $(SPACES) $(CAPTURE_FILES))$(filter PLAN-FAILED,$(EDGES)),)
$(error character.mk: cannot read $(CAPTURE)/capture.json or $(GRAPH) (message above))
endif
EDGES := $(filter-out PLAN-EMPTY,$(EDGES))
CAPTURE_FILES := $(addprefix $(CAPTURE)/,$(CAPTURE_FILES))
endif

A := $(OUT)/aligned
P := $(OUT)/parts
M := $(OUT)/motion
V := $(OUT)/previews
COMMON := --threads $(THREADS) --log-level $(LOG_LEVEL)
RUN = bash $(SURFCAP)/pipelines/step.sh $(OUT)/report/steps.tsv
tool = $(if $(filter yes,$(TRACK_TOOLS)),$(BIN)/surfcap-$(1))

TRUTH := $(CAPTURE)/ground_truth/database
ifeq ($(DATABASE),truth)
DB := $(TRUTH)/database.json
DB_FILES := $(DB) $(wildcard $(TRUTH)/template.* $(TRUTH)/sequences/*.npy)
else
DB := $(A)/database.json
DB_FILES := $(DB)
endif
GROUND_TRUTH := $(wildcard $(TRUTH)/database.json)

HISTOGRAMS := $(A)/similarity/histograms.npy $(A)/similarity/histograms.json
BLOCK_FILES := $(patsubst %,$(A)/similarity/rows/rows-%.npy,$(ROW_BLOCKS))
MATRIX := $(A)/similarity/matrix.npy
TREE := $(A)/similarity/tree.json
R := $(A)/register
SHARDS := $(if $(filter-out 1,$(REGISTER_JOBS)),$(shell seq 1 $(REGISTER_JOBS)))
SHARD_PARTS := $(foreach k,$(SHARDS),$(R)/shard-$(k)-of-$(REGISTER_JOBS).json)
ALIGNED := $(A)/database.json $(A)/template.ply $(foreach s,$(SEQUENCES),$(A)/sequences/$(s).npy $(A)/sequences/$(s).root.npy)
LEARNT := $(P)/parts.json
SPACE_FILES := $(foreach s,$(SPACES),$(M)/spaces/$(s)/space.json)
GRAPH_FILE := $(M)/graph.json
TRANSITION_FILES := $(foreach e,$(EDGES),$(M)/transitions/$(e).npy)
CHARACTER := $(OUT)/$(NAME).glb
PREVIEWS := $(V)/animation.glb $(V)/contact_sheet.png

.PHONY: all alignment similarity parts spaces graph transitions character previews clean tidy summary report
all: character previews
alignment: $(ALIGNED)
similarity: $(TREE)
parts: $(LEARNT)
spaces: $(SPACE_FILES)
graph: $(GRAPH_FILE)
transitions: $(TRANSITION_FILES)
character: $(CHARACTER)
previews: $(PREVIEWS)
clean:
	rm -rf $(A) $(P) $(M) $(V) $(CHARACTER) $(OUT)/$(NAME).png $(OUT)/report
# Quality figures, wall time per stage and where the results are (pipelines/summary.py).
summary:
	@python3 $(SURFCAP)/pipelines/summary.py $(OUT) --name $(NAME)
# The run report: one self-contained page; made after the other goals of the same command.
report: $(filter-out report summary tidy clean,$(MAKECMDGOALS))
	@bash $(SURFCAP)/scripts/vendor_three.sh $(THREE)
	@python3 $(SURFCAP)/pipelines/report.py $(OUT) --name $(NAME) --three $(THREE)
# Temporary files a killed step left (.<name>.tmp-<pid>-<n>); only while no step runs.
tidy:
	find $(OUT) -name '.*.tmp-*' -print -delete

$(BIN)/surfcap-%:
	@echo "character.mk: $@ is missing; build it first (./scripts/setup.sh)" >&2; exit 4

# ── alignment (surfcap-align, docs/align.md) ────────────────────────────────────────────────────
$(HISTOGRAMS) $(A)/report/histograms.json &: $(CAPTURE_FILES) $(call tool,align)
	rm -f $(A)/similarity/.histograms.*.tmp-*
	$(RUN) align.histograms $(A)/similarity/histograms.npy $(SUBMIT) $(BIN)/surfcap-align histograms \
	  --capture $(CAPTURE) --out $(A) $(HISTOGRAMS_OPTIONS) $(COMMON)

# One row block of the similarity matrix per job; merge joins them into the whole-matrix bytes.
$(A)/similarity/rows/rows-%.npy $(A)/report/similarity-rows-%.json: $(HISTOGRAMS) $(call tool,align)
	rm -f $(A)/similarity/rows/.rows-$*.npy.tmp-*
	$(RUN) align.similarity $@ $(SUBMIT) $(BIN)/surfcap-align similarity --out $(A) --rows $(subst -,:,$*) \
	  $(SIMILARITY_OPTIONS) $(COMMON)

$(MATRIX) $(A)/similarity/matrix.png &: $(BLOCK_FILES) $(call tool,align)
	find $(A)/similarity/rows -name '*rows-*' $(foreach b,$(ROW_BLOCKS),! -name rows-$(b).npy) -delete
	$(RUN) align.merge $(MATRIX) $(BIN)/surfcap-align merge --out $(A) $(COMMON)

$(TREE) $(A)/similarity/tree.png $(A)/report/similarity.json &: $(MATRIX) $(GROUND_TRUTH) $(call tool,align)
	$(RUN) align.tree $(TREE) $(BIN)/surfcap-align tree --out $(A) \
	  $(if $(GROUND_TRUTH),--ground-truth $(GROUND_TRUTH)) $(TREE_OPTIONS) $(COMMON)

ifeq ($(REGISTER_JOBS),1)
$(ALIGNED) $(A)/report/alignment.json &: $(TREE) $(CAPTURE_FILES) $(call tool,align)
	rm -rf $(A)/sequences $(R) $(A)/.database.json.tmp-* $(A)/.template.ply.tmp-*
	$(RUN) align.register $(A)/database.json $(SUBMIT) $(BIN)/surfcap-align register --out $(A) \
	  --capture $(CAPTURE) $(REGISTER_OPTIONS) $(COMMON)
else
# Registration jobs (docs/pipelines.md "Registration jobs"): the trunk of the tree, then K shards
# of its units, then the merge into the bytes the single job writes.
$(R)/trunk.json $(R)/trunk.npy $(A)/report/register-trunk.json &: $(TREE) $(CAPTURE_FILES) $(call tool,align)
	rm -f $(R)/.trunk.*.tmp-*
	$(RUN) align.register.trunk $(R)/trunk.json $(SUBMIT) $(BIN)/surfcap-align register --trunk --out $(A) \
	  --capture $(CAPTURE) $(REGISTER_OPTIONS) $(COMMON)

$(R)/shard-%-of-$(REGISTER_JOBS).json $(R)/shard-%-of-$(REGISTER_JOBS).npy \
    $(A)/report/register-shard-%-of-$(REGISTER_JOBS).json: $(R)/trunk.json $(CAPTURE_FILES) $(call tool,align)
	rm -f $(R)/.shard-$*-of-$(REGISTER_JOBS).*.tmp-*
	$(RUN) align.register.shard $(R)/shard-$*-of-$(REGISTER_JOBS).json $(SUBMIT) $(BIN)/surfcap-align register \
	  --shard $*/$(REGISTER_JOBS) --out $(A) --capture $(CAPTURE) $(REGISTER_OPTIONS) $(COMMON)

$(ALIGNED) $(A)/report/alignment.json &: $(R)/trunk.json $(SHARD_PARTS) $(call tool,align)
	rm -rf $(A)/sequences $(A)/.database.json.tmp-* $(A)/.template.ply.tmp-*
	find $(R) -name 'shard-*' $(foreach k,$(SHARDS),! -name 'shard-$(k)-of-$(REGISTER_JOBS).*') -delete
	$(RUN) align.register.merge $(A)/database.json $(SUBMIT) $(BIN)/surfcap-align register \
	  --merge $(REGISTER_JOBS) --out $(A) --capture $(CAPTURE) $(REGISTER_OPTIONS) $(COMMON)
endif

# ── part models (surfcap-learn, docs/learn.md) ──────────────────────────────────────────────────
$(LEARNT) $(P)/parts.png $(P)/report/learn.json &: $(DB_FILES) $(PARTS) $(call tool,learn)
	rm -rf $(P)
	$(RUN) learn $(LEARNT) $(SUBMIT) $(BIN)/surfcap-learn learn --database $(DB) --parts $(PARTS) \
	  --output $(P) $(LEARN_OPTIONS) $(COMMON)

# ── motion spaces, one job per space; graph.json once all are there (docs/blend.md) ─────────────
$(M)/spaces/%/space.json $(M)/report/spaces_%.json: $(DB_FILES) $(GRAPH) $(call tool,precompute)
	rm -rf $(M)/spaces/$*
	$(RUN) precompute.spaces $@ $(SUBMIT) $(BIN)/surfcap-precompute spaces --database $(DB) --graph $(GRAPH) \
	  --output $(M) --space $* --no-graph $(SPACES_OPTIONS) $(COMMON)

$(GRAPH_FILE): $(SPACE_FILES) $(GRAPH) $(call tool,precompute)
	$(RUN) precompute.graph $@ $(BIN)/surfcap-precompute graph --database $(DB) --graph $(GRAPH) \
	  --output $(M) $(COMMON)

# ── transitions, one job per edge FROM__TO ──────────────────────────────────────────────────────
edge_spaces = $(foreach s,$(subst __, ,$(1)),$(M)/spaces/$(s)/space.json)
$(M)/transitions/%.npy $(M)/transitions/%.json $(M)/transitions/%.png $(M)/report/transitions_%.json: $$(call edge_spaces,$$*) $(DB_FILES) $(GRAPH) \
    $(call tool,precompute)
	rm -f $(M)/transitions/.$*.*.tmp-*
	$(RUN) precompute.transitions $@ $(SUBMIT) $(BIN)/surfcap-precompute transitions --database $(DB) \
	  --graph $(GRAPH) --output $(M) --edge $(subst __,:,$*) --report $(M)/report/transitions_$*.json \
	  $(TRANSITIONS_OPTIONS) $(COMMON)

# ── packaging and previews ──────────────────────────────────────────────────────────────────────
$(CHARACTER) $(OUT)/$(NAME).png $(OUT)/report/export.json &: $(GRAPH_FILE) $(TRANSITION_FILES) $(LEARNT) $(DB_FILES) \
    $(call tool,export)
	rm -f $(OUT)/.$(NAME).glb.tmp-* $(OUT)/.$(NAME).png.tmp-*
	$(RUN) export $(CHARACTER) $(SUBMIT) $(BIN)/surfcap-export --database $(DB) --graph $(GRAPH_FILE) \
	  --parts $(LEARNT) --output $(CHARACTER) --name $(NAME) --report $(OUT)/report/export.json \
	  --preview $(OUT)/$(NAME).png \
	  $(EXPORT_OPTIONS) $(COMMON)

$(PREVIEWS) $(V)/report.json &: $(CHARACTER) $(CONTROL) $(call tool,play)
	rm -rf $(V)
	$(RUN) play $(V)/animation.glb $(SUBMIT) $(BIN)/surfcap-play --character $(CHARACTER) --script $(CONTROL) \
	  --output $(V) $(PLAY_OPTIONS) $(COMMON)
