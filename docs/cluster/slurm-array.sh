#!/usr/bin/env bash
# A learnpnp experiment (or reproduction) sharded over a Slurm job array: one
# task per shard, each writing its share of the runs into its own directory
# on a shared filesystem; a dependent job (slurm-merge.sh) merges them into
# what one machine would have written. Adapt the #SBATCH lines (partition,
# time, CPUs) and the defaults below, or set the variables when submitting.
# The cli crate's test `slurm_cluster` runs this script and slurm-merge.sh
# unchanged on a one-node Slurm cluster it starts (Debian's slurm-wlm and
# munge), with the variables set and --array and --cpus-per-task given on the
# sbatch command line, and checks that the merged result is the one-machine
# run's byte for byte.
#
#   jobid=$(sbatch --parsable docs/cluster/slurm-array.sh)          # the shards
#   sbatch --dependency=afterok:"${jobid%%;*}" docs/cluster/slurm-merge.sh
#
# The variables (sbatch passes the submitting shell's environment on; give
# both jobs the same SHARDS and OUT):
#   LEARNPNP   the command                       (default: learnpnp on PATH)
#   SHARDS     the number of shards, which the array must match: task ids
#              0 .. SHARDS-1 (--array on the command line overrides the line
#              below, e.g. SHARDS=4 sbatch --array=0-3 ...)    (default: 16)
#   OUT        the merged result's directory; shard I writes
#              ${OUT}-shards/shard-I                   (default: results/exp)
#   DOMAIN ALGO RUNS EPISODES SEED    the experiment (default: keepaway-
#              position, soft-sosmc, 64 runs of 10000 episodes, seed 2011)
# Relative paths are relative to the directory sbatch was run in.
#
#SBATCH --job-name=learnpnp-shards
#SBATCH --array=0-15                 # SHARDS tasks: 0 .. SHARDS-1
#SBATCH --cpus-per-task=4
#SBATCH --time=02:00:00
#SBATCH --output=learnpnp-shards-%A_%a.log
set -euo pipefail

LEARNPNP=${LEARNPNP:-learnpnp}
SHARDS=${SHARDS:-16}                 # must match --array
OUT=${OUT:-results/exp}
DOMAIN=${DOMAIN:-keepaway-position}
ALGO=${ALGO:-soft-sosmc}
RUNS=${RUNS:-64}
EPISODES=${EPISODES:-10000}
SEED=${SEED:-2011}

fail() {
    echo "slurm-array.sh: $*" >&2
    exit 2
}

[[ ${SHARDS} =~ ^[1-9][0-9]{0,5}$ ]] || fail "SHARDS must be a whole number from 1 to 999999, not '${SHARDS}'"
[[ ${OUT} =~ ^(.*[^/])/*$ ]] || fail "OUT must name a directory, not '${OUT}'"
OUT=${BASH_REMATCH[1]}
TASK=${SLURM_ARRAY_TASK_ID:-}
[[ ${TASK} =~ ^[0-9]+$ ]] || fail "not a task of a Slurm job array (submit with sbatch --array=0-$((SHARDS - 1)))"
TASK=$((10#${TASK}))
# The array must be exactly 0 .. SHARDS-1: a task outside it would play no
# shard, and a missing one would leave the merge without its shard.
if [[ ${SLURM_ARRAY_TASK_MIN:-0} != 0 || ${SLURM_ARRAY_TASK_MAX:-$((SHARDS - 1))} != $((SHARDS - 1)) ||
    ${SLURM_ARRAY_TASK_COUNT:-${SHARDS}} != "${SHARDS}" ]]; then
    fail "the array (tasks ${SLURM_ARRAY_TASK_MIN:-?}-${SLURM_ARRAY_TASK_MAX:-?}, ${SLURM_ARRAY_TASK_COUNT:-?} of them) does not match SHARDS=${SHARDS}: submit with --array=0-$((SHARDS - 1))"
fi
((TASK < SHARDS)) || fail "task ${TASK} is not a shard of SHARDS=${SHARDS}"
THREADS=${SLURM_CPUS_PER_TASK:-1}

# Every task runs the same experiment (same flags, same seed): run r goes to
# shard r % SHARDS and draws the seeds the whole experiment gives it.
"${LEARNPNP}" experiment "${DOMAIN}" --algo "${ALGO}" --runs "${RUNS}" --episodes "${EPISODES}" \
    --seed "${SEED}" --threads "${THREADS}" \
    --shard "${TASK}/${SHARDS}" --out "${OUT}-shards/shard-${TASK}"

# A reproduction shards the same way (and slurm-merge.sh merges it the same):
#   "${LEARNPNP}" reproduce 7.3 --shard "${TASK}/${SHARDS}" --out "${OUT}-shards/shard-${TASK}"
# An interrupted task continues with the same command and --resume.
