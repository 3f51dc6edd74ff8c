#!/usr/bin/env bash
# Regenerate the "Results" section of README.md: run the three paper studies, draw their figures
# into docs/figures/<study>/ and rewrite the tables of README.md (between its
# <!-- BEGIN report NAME --> / <!-- END report NAME --> markers) with `python -m engine report`.
#
# Usage:  bash scripts/results.sh [RANKS]        (RANKS: MPI ranks per study, default 2)
# Time here (2 shared cores, one rank): ~1 min (Section 7.1, 64²), ~3.5 min (Section 7.2, 64²),
#   ~3 min (Section 7.2, 32²), ~22 min (Section 7.3, 32²). Existing complete results are reused
#   (the engine resumes); delete results/ or pass FRESH=1 to recompute.
# The 64² Section 7.3 study (studies/section_7_3_orthotropic.toml) is not run here; see its header.
set -euo pipefail
cd "$(dirname "$0")/.."
ranks="${1:-2}"
fresh=()
[[ "${FRESH:-0}" == "1" ]] && fresh=(--fresh)
python=.venv/bin/python
for study in section_7_1_static section_7_2_cyclic section_7_2_cyclic_32 \
    section_7_3_orthotropic_32; do
    .venv/bin/mpiexec -n "$ranks" "$python" -m engine "studies/$study.toml" \
        --no-progress-bar "${fresh[@]}"
    "$python" -m engine plot "results/$study.h5" --out "docs/figures/$study"
    "$python" -m engine report "results/$study.h5" --update README.md
done
