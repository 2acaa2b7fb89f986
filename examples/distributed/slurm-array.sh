#!/usr/bin/env bash
# A plan's shards as a Slurm job array (docs/scaling.md). Write the plan on a file system every
# node sees, then submit this script with the number of shards as the array:
#
#   cierva uncertainty cases/ --samples 256 --plan /shared/study
#   sbatch --array=1-64 slurm-array.sh /shared/study 64
#   sbatch --dependency=afterany:<the array's job id> --wrap \
#     "cierva uncertainty --from-plan /shared/study > /shared/study/uncertainty.txt"
#
# Each task runs one shard on the cores Slurm gives it (cierva uses the task's allocation, as
# its affinity sets it). A task that fails or is preempted can simply be submitted again
# (`sbatch --array=17 ...`): the shard takes up where it stopped, and `--from-plan` names any
# shard still missing. `afterany`, not `afterok`: the merge should run and say what is missing.
#SBATCH --job-name=cierva-shard
#SBATCH --cpus-per-task=1
#SBATCH --time=04:00:00
#SBATCH --output=cierva-shard-%A_%a.log
set -euo pipefail
plan=$1
shards=$2
exec cierva --quiet evaluate "$plan" --shard "${SLURM_ARRAY_TASK_ID}/${shards}"
