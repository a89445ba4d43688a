#!/bin/sh
# Run a command (usually pvpython) under a private Xvfb server:
#   postproc/headless.sh pvpython postproc/render_flock.py out/flock snapshot.png
# Xvfb chooses a free display itself and reports it once it accepts connections (-displayfd), so
# back-to-back or parallel renders cannot collide on a display number. `xvfb-run -a` guesses the
# number from lock files and does not wait for a server that fails to start; in CI that ended as
# "bad X server connection. DISPLAY=:100" and a SIGABRT in pvpython.
set -u
command -v Xvfb >/dev/null 2>&1 || { echo "headless.sh: Xvfb not found (apt install xvfb)" >&2; exit 127; }
[ $# -ge 1 ] || { echo "usage: headless.sh COMMAND [ARGS...]" >&2; exit 2; }

tmp=$(mktemp -d)
xpid=
stop_server() {
  [ -n "$xpid" ] && kill "$xpid" 2>/dev/null && wait "$xpid" 2>/dev/null
  xpid=
}
trap 'stop_server; rm -rf "$tmp"' EXIT INT TERM

display=
for attempt in 1 2 3; do
  : >"$tmp/display"
  Xvfb -displayfd 3 -screen 0 1280x1024x24 -nolisten tcp 3>"$tmp/display" 2>"$tmp/xvfb.log" &
  xpid=$!
  waited=0
  while [ ! -s "$tmp/display" ] && kill -0 "$xpid" 2>/dev/null && [ $waited -lt 200 ]; do
    sleep 0.05
    waited=$((waited + 1))
  done
  display=$(head -n 1 "$tmp/display" 2>/dev/null)
  [ -n "$display" ] && break
  stop_server
  echo "headless.sh: Xvfb did not start (attempt $attempt): $(tail -n 1 "$tmp/xvfb.log")" >&2
done
[ -n "$display" ] || { echo "headless.sh: no X server after 3 attempts" >&2; exit 1; }

DISPLAY=":$display" "$@"
status=$?
exit $status
