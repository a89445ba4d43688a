#!/usr/bin/env bash
# Render a batch job for any deck from jobs/batch/biota.{slurm,pbs} and submit it.
#
#   jobs/submit.sh slurm|pbs DECK [options] [-- biota run arguments, e.g. --set run.end_time=20]
#     --nodes N            nodes (1)
#     --tasks-per-node N   MPI ranks per node (default: cores of this machine)
#     --time T             wall-time limit per segment, [D-]HH:MM:SS (01:00:00)
#     --margin S           warning seconds before the limit: one step + one checkpoint (120)
#     --requeues N         segments after the first, at most (20)
#     --name NAME          job name (scenario name of the deck)
#     --run-dir DIR        output.dir, checkpoints in DIR/checkpoints (runs/NAME)
#     --partition P        SLURM partition / PBS queue;  --account A: account to charge
#     --dry-run            print the rendered script, submit nothing
#
# The rendered script is written to RUN_DIR/NAME.<slurm|pbs> and submitted with sbatch or qsub.
# Each segment continues from the newest checkpoint in RUN_DIR/checkpoints until run.end_time.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
usage() { sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
(($# >= 2)) || usage
SCHED=$1 DECK=$2
shift 2
[[ $SCHED == slurm || $SCHED == pbs ]] || { echo "submit.sh: scheduler '$SCHED' is not slurm or pbs" >&2; exit 2; }
[[ -f $DECK ]] || { echo "submit.sh: deck '$DECK' does not exist" >&2; exit 2; }
NODES=1 TPN=$(nproc) TIME=01:00:00 MARGIN=120 REQUEUES=20 NAME="" RUN_DIR="" PART="" ACCOUNT="" DRY=0
EXTRA=()
while (($#)); do
  case $1 in
    --nodes) NODES=$2; shift 2 ;;
    --tasks-per-node) TPN=$2; shift 2 ;;
    --time) TIME=$2; shift 2 ;;
    --margin) MARGIN=$2; shift 2 ;;
    --requeues) REQUEUES=$2; shift 2 ;;
    --name) NAME=$2; shift 2 ;;
    --run-dir) RUN_DIR=$2; shift 2 ;;
    --partition) PART=$2; shift 2 ;;
    --account) ACCOUNT=$2; shift 2 ;;
    --dry-run) DRY=1; shift ;;
    --) shift; EXTRA=("$@"); break ;;
    *) echo "submit.sh: unknown option '$1'" >&2; usage ;;
  esac
done
for v in NODES TPN MARGIN REQUEUES; do
  [[ ${!v} =~ ^[0-9]+$ ]] || { echo "submit.sh: $v='${!v}' is not a whole number" >&2; exit 2; }
done
DECK=$(cd "$(dirname "$DECK")" && pwd)/$(basename "$DECK")
if [[ -z $NAME ]]; then
  NAME=$(sed -n 's/^[[:space:]]*scenario[[:space:]]*=[[:space:]]*"\([^"]*\)".*/\1/p' "$DECK" | head -n 1)
  NAME=${NAME:-biota}
fi
RUN_DIR=$(realpath -m "${RUN_DIR:-runs/$NAME}")
SCRIPT="$RUN_DIR/$NAME.$SCHED"

extra_q=""
for a in "${EXTRA[@]+"${EXTRA[@]}"}"; do extra_q+="${extra_q:+ }$(printf '%q' "$a")"; done
if [[ $SCHED == slurm ]]; then
  part_line=${PART:+SBATCH --partition=$PART} acct_line=${ACCOUNT:+SBATCH --account=$ACCOUNT}
else
  part_line=${PART:+PBS -q $PART} acct_line=${ACCOUNT:+PBS -A $ACCOUNT}
fi
t=$(<"$ROOT/jobs/batch/biota.$SCHED")
t=${t//@JOB_NAME@/$NAME}
t=${t//@NODES@/$NODES}
t=${t//@TASKS_PER_NODE@/$TPN}
t=${t//@NRANKS@/$((NODES * TPN))}
t=${t//@TIME@/$TIME}
t=${t//@SIGNAL_MARGIN@/$MARGIN}
t=${t//@MAX_REQUEUES@/$REQUEUES}
t=${t//@DECK@/$DECK}
t=${t//@RUN_DIR@/$RUN_DIR}
t=${t//@BIOTA_ROOT@/$ROOT}
t=${t//@JOB_SCRIPT@/$SCRIPT}
t=${t//@EXTRA_ARGS@/$extra_q}
t=${t//@PARTITION_LINE@/$part_line}
t=${t//@ACCOUNT_LINE@/$acct_line}
if ((DRY)); then
  printf '%s\n' "$t"
  echo "# (dry run: would write $SCRIPT and run: $([[ $SCHED == slurm ]] && echo sbatch || echo qsub) $SCRIPT)" >&2
  exit 0
fi
mkdir -p "$RUN_DIR"
printf '%s\n' "$t" >"$SCRIPT"
chmod +x "$SCRIPT"
echo "submit.sh: wrote $SCRIPT"
if [[ $SCHED == slurm ]]; then sbatch "$SCRIPT"; else qsub "$SCRIPT"; fi
