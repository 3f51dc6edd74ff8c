#!/usr/bin/env bash
# Regenerate docs/explanation/results.md: run the paper's Section 7 studies, draw their figures into
# docs/figures/<study>/ (64² studies) and rewrite the tables of docs/explanation/results.md (between its
# <!-- BEGIN report NAME --> / <!-- END report NAME --> markers) with `python -m engine report`.
#
# Usage:  bash scripts/results.sh [RANKS]        (RANKS: MPI ranks per study, default 2)
#         FRESH=1 bash scripts/results.sh        (recompute instead of reusing complete results)
#         STUDIES="section_7_1_static" bash scripts/results.sh   (a subset)
# Existing complete results are reused (the engine resumes); the figures and tables are
# redrawn every time. The time of each study is in its header (studies/*.toml).
set -euo pipefail
cd "$(dirname "$0")/.."
ranks="${1:-2}"
fresh=()
[[ "${FRESH:-0}" == "1" ]] && fresh=(--fresh)
python=.venv/bin/python
studies=${STUDIES:-"section_7_1_static section_7_2_cyclic section_7_2_cyclic_32 \
section_7_3_orthotropic section_7_3_orthotropic_32"}
for study in $studies; do
    start=$SECONDS
    .venv/bin/mpiexec -n "$ranks" "$python" -m engine "studies/$study.toml" \
        --no-progress-bar "${fresh[@]}"
    echo "results.sh: $study computed in $((SECONDS - start)) s"
    # the manual shows the figures of the paper's mesh; the 32² studies give tables only
    [[ "$study" == *_32 ]] || "$python" -m engine plot "results/$study.h5" --out "docs/figures/$study"
    "$python" -m engine report "results/$study.h5" --update docs/explanation/results.md
done
