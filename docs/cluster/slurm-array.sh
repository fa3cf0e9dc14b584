#!/usr/bin/env bash
# A learnpnp experiment (or reproduction) sharded over a Slurm job array: one
# task per shard, each writing its share of the runs into its own directory
# on a shared filesystem; a dependent job merges them into what one machine
# would have written. Not run here: adapt the paths, partition and sizes.
#
#   sbatch docs/cluster/slurm-array.sh            # the shards
#   sbatch --dependency=afterok:<array job id> --wrap \
#       "learnpnp merge results/exp results/exp-shards/shard-*"
#
#SBATCH --job-name=learnpnp-shards
#SBATCH --array=0-15                 # SHARDS tasks: 0 .. SHARDS-1
#SBATCH --cpus-per-task=4
#SBATCH --time=02:00:00
#SBATCH --output=results/exp-shards/slurm-%A_%a.log
set -euo pipefail

SHARDS=16                            # must match --array
OUT=results/exp-shards/shard-${SLURM_ARRAY_TASK_ID}

# Every task runs the same experiment (same flags, same seed): run r goes to
# shard r % SHARDS and draws the seeds the whole experiment gives it.
learnpnp experiment keepaway-position --algo soft-sosmc --runs 64 --episodes 10000 \
    --seed 2011 --threads "${SLURM_CPUS_PER_TASK}" \
    --shard "${SLURM_ARRAY_TASK_ID}/${SHARDS}" --out "${OUT}"

# A reproduction shards the same way:
#   learnpnp reproduce 7.3 --shard "${SLURM_ARRAY_TASK_ID}/${SHARDS}" --out "${OUT}"
# An interrupted task continues with the same command and --resume.
