# Sourced by the batch templates (jobs/batch/biota.slurm, jobs/batch/biota.pbs): one job segment of
# a run that may span several scheduler allocations.
#
#   biota_job_segment <requeue-count> <launcher...>
#
# 1. Restart: the newest complete checkpoint in $RUN_DIR/checkpoints, if any (first segment: none).
# 2. Launch `<launcher...> $BIOTA run $DECK ...` in the background, so that the shell can run its
#    trap while the ranks compute (bash runs traps only between commands; `wait` is interruptible).
# 3. On the scheduler's warning signal (TERM or USR1 to this shell), send SIGUSR1 to the launcher.
#    srun and OpenMPI's mpirun/mpiexec forward SIGUSR1 to every rank and keep waiting; Biota then
#    writes a checkpoint at the end of the current step and exits 0. (SIGTERM to mpirun would do
#    the same, but mpirun SIGKILLs the ranks 1 s later, odls_base_sigkill_timeout.)
# 4. Then: "end of run" checkpoint in the log -> done; signal checkpoint -> requeue through
#    $REQUEUE_CMD (unless MAX_REQUEUES is reached); anything else -> the job fails with Biota's code.
#
# Needs: DECK RUN_DIR BIOTA EXTRA_ARGS (array) MAX_REQUEUES REQUEUE_CMD (array), set by the template.

biota_log() { echo "biota-job: $*"; }

BIOTA_DEADLINE=${BIOTA_DEADLINE:-0}

# The warning signal (or our deadline): ask every rank for a checkpoint, once.
biota_warn() {
  ((BIOTA_SIGNALLED)) && return 0
  BIOTA_SIGNALLED=1
  biota_log "warning signal: asking the ranks for a checkpoint (SIGUSR1 to the launcher)"
  kill -USR1 "$BIOTA_LAUNCHER_PID" 2>/dev/null || true
}

# Newest complete checkpoint (<scenario>_<step>.h5; a .h5.tmp is an unfinished write), by step.
biota_newest_checkpoint() {
  local dir="$1"
  ls "$dir"/*_[0-9]*.h5 2>/dev/null | sort -V | tail -n 1
}

# --restart arguments for this segment: `latest` when this biota understands it, else the path.
biota_restart_args() {
  local newest
  newest=$(biota_newest_checkpoint "$RUN_DIR/checkpoints")
  [[ -z $newest ]] && return 0
  if "$BIOTA" run --help 2>/dev/null | grep -qi -- 'latest'; then
    echo "--restart latest"
  else
    echo "--restart $newest"
  fi
}

biota_job_segment() {
  local count="$1"
  shift
  local -a launcher=("$@")
  mkdir -p "$RUN_DIR"
  local seg_log="$RUN_DIR/segment_${count}.log"
  local -a restart
  read -r -a restart <<<"$(biota_restart_args)"
  local -a cmd=("${launcher[@]}" "$BIOTA" run "$DECK" --set "output.dir=$RUN_DIR"
    --set "checkpoint.dir=$RUN_DIR/checkpoints" "${EXTRA_ARGS[@]}" "${restart[@]}")
  biota_log "segment $count on $(hostname), $(date -u +%FT%TZ): ${cmd[*]}"

  BIOTA_SIGNALLED=0
  "${cmd[@]}" >"$seg_log" 2>&1 &
  BIOTA_LAUNCHER_PID=$!
  tail -n +1 -f --pid="$BIOTA_LAUNCHER_PID" "$seg_log" &  # live copy in the scheduler's log
  local tail_pid=$!
  trap 'biota_warn' TERM USR1
  # Poll rather than block in `wait`: one loop serves the scheduler's signal (trap) and, where the
  # scheduler sends none early enough (PBS), our own deadline $BIOTA_DEADLINE (epoch s, 0: none).
  while kill -0 "$BIOTA_LAUNCHER_PID" 2>/dev/null; do
    if ((BIOTA_DEADLINE > 0 && BIOTA_SIGNALLED == 0 && $(date +%s) >= BIOTA_DEADLINE)); then
      biota_log "deadline of this allocation reached"
      biota_warn
    fi
    sleep 1 &
    wait $! 2>/dev/null
  done
  local rc=0
  wait "$BIOTA_LAUNCHER_PID"
  rc=$?
  trap - TERM USR1
  wait "$tail_pid"

  if ((rc != 0)); then
    biota_log "biota exited with $rc: not requeued (last checkpoint: $(biota_newest_checkpoint "$RUN_DIR/checkpoints"))"
    return "$rc"
  fi
  if grep -q "checkpoint (end of run) written" "$seg_log"; then
    biota_log "run complete after $((count + 1)) segment(s)"
    return 0
  fi
  if grep -q "checkpoint (signal) written" "$seg_log" || ((BIOTA_SIGNALLED)); then
    if ((count >= MAX_REQUEUES)); then
      biota_log "stopped by the time limit and MAX_REQUEUES=$MAX_REQUEUES reached: not requeued"
      return 3
    fi
    biota_log "stopped by the time limit: requeue $((count + 1)) with ${REQUEUE_CMD[*]}"
    "${REQUEUE_CMD[@]}"
    return $?
  fi
  biota_log "biota exited 0 without an end-of-run or signal checkpoint; see $seg_log"
  return 4
}

# Seconds in a [[D-]HH:]MM:SS walltime (PBS and SLURM forms).
biota_walltime_seconds() {
  local t="$1" d=0 h=0 m=0 s=0
  if [[ $t == *-* ]]; then d=${t%%-*}; t=${t#*-}; fi
  IFS=: read -r -a f <<<"$t"
  case ${#f[@]} in
    3) h=${f[0]} m=${f[1]} s=${f[2]} ;;
    2) m=${f[0]} s=${f[1]} ;;
    1) m=${f[0]} ;;
  esac
  echo $(((10#$d * 24 + 10#$h) * 3600 + 10#$m * 60 + 10#$s))
}
