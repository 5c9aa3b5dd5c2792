#!/bin/bash
# A ten-minute lesson at 80x24 in tmux (issue 13): the ε trade-off on Benchmark 1, the mesh-size
# story on lesson-mesh, the eight-obstacle enumeration refusing. Prints the pane after each
# step. Needs tmux; run from the repository after `cargo build --release`.
B=${1:-target/release/beamfric}
S=lesson
tmux kill-session -t $S 2>/dev/null
tmux new-session -d -s $S -x 80 -y 24 "$B benchmark-1"
sleep 1.5
step() {
  for k in "$@"; do tmux send-keys -t $S "$k"; sleep 0.1; done
  sleep ${WAIT:-1.5}
  echo "### $DESC  [keys: $*]"; tmux capture-pane -p -t $S; echo
}
DESC="1 start: Benchmark 1" step
DESC="2 type the method: regularized" step G Enter r e g u l a r i z e d Enter
DESC="3 ε row, type 1e-2" step Up Up Enter 1 e - 2 Enter
DESC="4 Tab: error vs ε" step Tab
DESC="5 Tab: cond vs ε" step Tab
DESC="6 ε = 1e-12" step Enter 1 e - 1 2 Enter
DESC="7 warnings view" step w
DESC="8 close, back to the deflection" step Escape Tab Tab
DESC="9 preset picker, search lesson-mesh" step p l e s s o n - m e s h
DESC="10 load lesson-mesh (discard changes: y)" step Enter y
DESC="11 the mesh-size panel" step Tab Tab Tab
WAIT=5 DESC="12 elements 200000 (dual)" step G Up Enter 2 0 0 0 0 0 Enter
DESC="13 warnings view" step w
DESC="14 close, condensed" step Escape G Enter c o n d e n s e d Enter
DESC="15 eight obstacles" step p e i g h t Enter y
DESC="16 regularized on eight obstacles" step G Enter r e g u l a r i z e d Enter
DESC="17 warnings/error view" step w
tmux send-keys -t $S Escape; sleep 0.3; tmux send-keys -t $S q; sleep 0.5; tmux send-keys -t $S y; sleep 0.5
tmux kill-session -t $S 2>/dev/null
