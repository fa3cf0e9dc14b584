#!/usr/bin/env bash
# Merges the shards slurm-array.sh wrote into what one machine would have
# written, as a job that starts once every task of the array has succeeded:
#
#   jobid=$(sbatch --parsable docs/cluster/slurm-array.sh)
#   sbatch --dependency=afterok:"${jobid%%;*}" docs/cluster/slurm-merge.sh
#
# Give it the same LEARNPNP, SHARDS and OUT as the array (see slurm-array.sh):
# it merges ${OUT}-shards/shard-0 .. shard-(SHARDS-1) into ${OUT}. A merge is
# refused, with the reason, when a shard is missing, partial or of another
# experiment. The cli crate's test `slurm_cluster` runs it on a one-node
# Slurm cluster.
#
#SBATCH --job-name=learnpnp-merge
#SBATCH --cpus-per-task=1
#SBATCH --time=00:30:00
#SBATCH --output=learnpnp-merge-%j.log
set -euo pipefail

LEARNPNP=${LEARNPNP:-learnpnp}
SHARDS=${SHARDS:-16}
OUT=${OUT:-results/exp}

fail() {
    echo "slurm-merge.sh: $*" >&2
    exit 2
}

[[ ${SHARDS} =~ ^[1-9][0-9]{0,5}$ ]] || fail "SHARDS must be a whole number from 1 to 999999, not '${SHARDS}'"
[[ ${OUT} =~ ^(.*[^/])/*$ ]] || fail "OUT must name a directory, not '${OUT}'"
OUT=${BASH_REMATCH[1]}

shards=()
for ((i = 0; i < SHARDS; i++)); do
    shards+=("${OUT}-shards/shard-${i}")
done
"${LEARNPNP}" merge "${OUT}" "${shards[@]}"
