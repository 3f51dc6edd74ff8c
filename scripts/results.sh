#!/usr/bin/env bash
# Regenerate the "Results" section of README.md: run the three paper studies, draw their figures
# into docs/figures/<study>/ and rewrite the tables of README.md (between its
# <!-- BEGIN report NAME --> / <!-- END report NAME --> markers) with `python -m engine report`.
#
# Usage:  bash scripts/results.sh [RANKS]        (RANKS: MPI ranks per study, default 2)
# Time here (2 ranks, idle machine, measured): 7 s (Section 7.1, 64²), 86 s (Section 7.2, 64²),
#   14 s (Section 7.2, 32²), ~9.5 min (Section 7.3, 64²), 86 s (Section 7.3, 32²): about 13
#   minutes in all.
#   Existing complete results are reused
#   (the engine resumes); delete results/ or pass FRESH=1 to recompute.
set -euo pipefail
cd "$(dirname "$0")/.."
ranks="${1:-2}"
fresh=()
[[ "${FRESH:-0}" == "1" ]] && fresh=(--fresh)
python=.venv/bin/python
for study in section_7_1_static section_7_2_cyclic section_7_2_cyclic_32 \
    section_7_3_orthotropic section_7_3_orthotropic_32; do
    .venv/bin/mpiexec -n "$ranks" "$python" -m engine "studies/$study.toml" \
        --no-progress-bar "${fresh[@]}"
    "$python" -m engine plot "results/$study.h5" --out "docs/figures/$study"
    "$python" -m engine report "results/$study.h5" --update README.md
done
