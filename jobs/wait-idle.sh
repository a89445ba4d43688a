# shellcheck shell=bash
# Sourced by the benchmark jobs (bench-speed.sh, seaweed-weak-scaling.sh). The 1-minute load lags:
# after a 2-rank run it stays near 2 for a minute, and a benchmark started then cannot be told from
# one that shared the cores. wait_idle waits, at most 5 minutes, until the load is below 1.0, and
# says how long it waited if it waited at all.
wait_idle() {
  local waited=0
  while awk '{exit !($1 >= 1.0)}' /proc/loadavg && [ $waited -lt 300 ]; do
    sleep 5
    waited=$((waited + 5))
  done
  [ $waited -eq 0 ] || echo "(waited ${waited} s for the 1-minute load to fall below 1.0)"
}
