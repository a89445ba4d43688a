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

# Accepting connections is checked with a real client (XOpenDisplay through ctypes) before the
# command runs; server start-up is serialised by a lock so concurrent renders cannot race for a
# display number (seen: two servers reporting displays of which one refused connections).
# -noreset: an X server resets when its last client disconnects, and the probe is that client.
# A render that connected during the reset got "bad X server connection" in 1 of 12 renders,
# all three runs of one render alike; with -noreset, 0 of 40 (docs/decisions.md).
x_accepts() {
  python3 -c "import ctypes,sys; x=ctypes.cdll.LoadLibrary('libX11.so.6'); x.XOpenDisplay.restype=ctypes.c_void_p; d=x.XOpenDisplay(sys.argv[1].encode()); sys.exit(0 if d else 1)" ":$1" 2>/dev/null
}
start_server() {
  for attempt in 1 2 3; do
    : >"$tmp/display"
    Xvfb -displayfd 3 -screen 0 1280x1024x24 -nolisten tcp -noreset 3>"$tmp/display" 2>"$tmp/xvfb.log" &
    xpid=$!
    waited=0
    while [ ! -s "$tmp/display" ] && kill -0 "$xpid" 2>/dev/null && [ $waited -lt 200 ]; do
      sleep 0.05
      waited=$((waited + 1))
    done
    display=$(head -n 1 "$tmp/display" 2>/dev/null)
    [ -n "$display" ] && x_accepts "$display" && return 0
    stop_server
    display=
    echo "headless.sh: Xvfb did not start (attempt $attempt): $(tail -n 1 "$tmp/xvfb.log")" >&2
    sleep 1
  done
  return 1
}

run_once() {
  display=
  if command -v flock >/dev/null 2>&1; then
    exec 9>"${TMPDIR:-/tmp}/biota-headless.lock"
    flock -w 120 9
    start_server
    flock -u 9
    exec 9>&-
  else
    start_server
  fi
  [ -n "$display" ] || { echo "headless.sh: no X server after 3 attempts" >&2; return 1; }
  DISPLAY=":$display" "$@" 2>"$tmp/stderr"
  status=$?
  cat "$tmp/stderr" >&2
  stop_server
  return $status
}

# A render that still loses its X connection (VTK: "bad X server connection", SIGABRT) is run
# again on a fresh server, at most three times in all.
for run in 1 2 3; do
  run_once "$@"
  status=$?
  grep -q "bad X server connection" "$tmp/stderr" 2>/dev/null || break
  echo "headless.sh: the X connection was lost (run $run), starting a new server" >&2
done
exit $status
