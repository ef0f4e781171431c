#!/usr/bin/env bash
# Smoke test of the real workbench binary in a real terminal (tmux): it starts on the built-in
# default study, draws it, quits on `q` with exit code 0 and leaves the alternate screen with
# the cursor visible. Usage: tests/tui_smoke.sh path/to/rocklab
# Exit codes: 0 pass, 1 fail, 77 skipped (no tmux).
set -uo pipefail
BIN=${1:?usage: tui_smoke.sh path/to/rocklab}
if ! command -v tmux >/dev/null 2>&1; then
  echo "SKIP: tmux is not installed"
  exit 77
fi
SOCK="rocklab-smoke-$$"
SESSION=smoke
OUT=$(mktemp -d)
# A foreground colour escape as tmux reports it (palette, 256-colour or RGB).
COLOUR=$'\e''\[([0-9;]*;)?(3[0-7]|9[0-7]|38;[25];[0-9;]+)m'
tm() { tmux -L "$SOCK" -f /dev/null "$@"; }
cleanup() { tm kill-server >/dev/null 2>&1; rm -rf "$OUT"; }
trap cleanup EXIT
fail() {
  echo "FAIL: $*"
  echo "--- screen ---"
  tm capture-pane -p -t "$SESSION" 2>/dev/null || true
  exit 1
}

# Start the session running command $1. Retried: after `kill-session` of its last session the
# server is still exiting for a moment, and a client that reaches it then gets "server exited
# unexpectedly" (seen once under load in CI).
start() {
  for _ in 1 2 3 4 5; do
    tm new-session -d -s "$SESSION" -x 80 -y 24 "$1" 2>/dev/null && return 0
    sleep 0.5
  done
  fail "cannot start tmux"
}

# Wait (at most $1 tenths of a second) until the pane shows the text $2.
wait_for() {
  local tries=$1 text=$2
  for _ in $(seq "$tries"); do
    if tm capture-pane -p -t "$SESSION" 2>/dev/null | grep -qF -- "$text"; then
      return 0
    fi
    sleep 0.1
  done
  return 1
}

# The shell line after the binary prints its exit code once the workbench has exited; the
# pane stays open so that the screen it left behind can be inspected.
start "env -u NO_COLOR TERM=xterm-256color '$BIN'; echo \"rocklab-exit=\$?\" > '$OUT/exit'; echo rocklab-exited; sleep 60"

wait_for 100 "Study" || fail "the workbench did not draw within 10 s"
wait_for 50 "scenes in" || fail "the default study summary (scene count) is not drawn"
wait_for 10 "q quit" || fail "the status line with key hints is not drawn"
[ "$(tm display -p -t "$SESSION" '#{alternate_on}')" = 1 ] || fail "the workbench is not on the alternate screen"

# Colours are on by default (foreground colour escapes in the pane)...
tm capture-pane -e -p -t "$SESSION" | grep -qE "$COLOUR" || fail "no colours drawn without NO_COLOR"

# A resize below the minimum shows a notice; back to 80×24 redraws the study.
tm resize-window -t "$SESSION" -x 30 -y 8
wait_for 50 "too small" || fail "no notice after resizing to 30×8"
tm resize-window -t "$SESSION" -x 80 -y 24
wait_for 50 "scenes in" || fail "the study was not redrawn after resizing back to 80×24"

# The help overlay opens and closes.
tm send-keys -t "$SESSION" '?'
wait_for 30 "everywhere" || fail "? did not open the help overlay"
tm send-keys -t "$SESSION" Escape
sleep 0.3

tm send-keys -t "$SESSION" q
wait_for 100 "rocklab-exited" || fail "q did not end the workbench within 10 s"
grep -qx "rocklab-exit=0" "$OUT/exit" || fail "exit status: $(cat "$OUT/exit")"
[ "$(tm display -p -t "$SESSION" '#{alternate_on}')" = 0 ] || fail "the terminal was left on the alternate screen"
[ "$(tm display -p -t "$SESSION" '#{cursor_flag}')" = 1 ] || fail "the cursor was left hidden"
# Raw mode off: the shell's output has normal line endings (raw mode would not map \n to \r\n,
# leaving the second line indented).
tm capture-pane -p -t "$SESSION" | grep -qx "rocklab-exited" || fail "the terminal was left in raw mode"

# ...and off under NO_COLOR: no colour escapes at all, only reverse video and bold.
tm kill-session -t "$SESSION"
start "NO_COLOR=1 TERM=xterm-256color '$BIN'; echo \"rocklab-exit=\$?\" > '$OUT/exit'; echo rocklab-exited; sleep 60"
wait_for 100 "scenes in" || fail "the workbench did not draw under NO_COLOR"
if tm capture-pane -e -p -t "$SESSION" | grep -qE "$COLOUR"; then
  fail "colours drawn under NO_COLOR"
fi
tm send-keys -t "$SESSION" q
wait_for 100 "rocklab-exited" || fail "q did not end the workbench under NO_COLOR"
grep -qx "rocklab-exit=0" "$OUT/exit" || fail "exit status under NO_COLOR: $(cat "$OUT/exit")"

# The Fig. 8 scene (bare block, ωg/p = 4; a sweep stops it once settled at 1.2 s) opened from
# its results: the Scene screen shows the whole 15 s with all its impacts.
cat > "$OUT/fig8.ron" <<'STUDY'
(
    version: 1,
    name: "fig8_scene",
    description: "Fig. 8 scene: bare rigid block, one-sine pulse A/(g·α) = 1.5, ωg/p = 4",
    structure: rigid(p: 2.0, alpha: 0.17453292519943295),
    devices: [none],
    excitation: pulse(shape: sine, amplitude: alpha_ratio(1.5), frequency: ratio([4.0])),
    quantities: [peak_rotation_ratio],
    duration: 15.0,
)
STUDY
"$BIN" run "$OUT/fig8.ron" --out "$OUT/fig8" --quiet >/dev/null 2>&1 || fail "rocklab run of the Fig. 8 scene failed"
tm kill-session -t "$SESSION"
start "TERM=xterm-256color '$BIN' tui '$OUT/fig8'; echo \"rocklab-exit=\$?\" > '$OUT/exit'; echo rocklab-exited; sleep 60"
wait_for 100 "Enter: open scene" || fail "the Fig. 8 results did not open"
tm send-keys -t "$SESSION" Enter
wait_for 100 "0–15 s: impacts" || fail "the Fig. 8 scene view does not cover 15 s"
impacts=$(tm capture-pane -p -t "$SESSION" | sed -n 's/.*0–15 s: impacts \([0-9]*\).*/\1/p' | head -1)
[ "${impacts:-0}" -ge 20 ] || fail "the Fig. 8 scene view counts ${impacts:-no} impacts over 15 s, not 20 or more"
tm capture-pane -p -t "$SESSION" | grep -qF "t (s)" || fail "the scene's time axis has no unit"
if tm capture-pane -p -t "$SESSION" | grep -qE "flywheel|clutch"; then
  fail "device charts drawn for a bare block"
fi
tm send-keys -t "$SESSION" q
wait_for 100 "rocklab-exited" || fail "q did not end the workbench from the Scene screen"
grep -qx "rocklab-exit=0" "$OUT/exit" || fail "exit status after the scene view: $(cat "$OUT/exit")"
# A lost terminal (the tmux session killed, as a dropped SSH connection does): the workbench
# ends instead of spinning in its input loop.
tm kill-session -t "$SESSION"
start "echo \$\$ > '$OUT/pid'; exec env TERM=xterm-256color '$BIN' tui"
wait_for 100 "1 Study" || fail "the workbench did not draw before the hangup test"
pid=$(cat "$OUT/pid")
tm kill-session -t "$SESSION"
for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
if kill -0 "$pid" 2>/dev/null; then
  kill -9 "$pid"
  fail "the workbench kept running 10 s after its terminal was gone"
fi
echo "PASS: workbench drew the default study in colour and under NO_COLOR, handled resizes, exited cleanly on q, showed the Fig. 8 scene over 15 s with $impacts impacts, and ended when its terminal was gone"
