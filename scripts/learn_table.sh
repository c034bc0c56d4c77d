#!/usr/bin/env bash
# The learned grammar of each gallery example against its export: rules, units not
# explained, the worst of ten frames drawn by gmotion's own renderer (docs/learn.md).
# Usage: scripts/learn_table.sh NAME… (run from an empty folder; CARGO_TARGET_DIR as built).
set -u
ROOT=$(cd "$(dirname "$0")/.." && pwd)
G=${GMOTION:-${CARGO_TARGET_DIR:-$ROOT/target}/quick/gmotion}
for g in "$@"; do
  $G animate $ROOT/grammars/$g.gm -o t_$g.json >/dev/null 2>&1 || { echo "$g: animate failed"; continue; }
  s=$(date +%s.%N)
  if ! $G learn t_$g.json -o t_${g}_l.gm > t_${g}_r.txt 2>t_${g}_e.txt; then echo "$g | $(head -c 150 t_${g}_e.txt)"; continue; fi
  e=$(date +%s.%N)
  hand=$(grep -cE '^\s*[a-zA-Z_]+(\(.*)?\s*:' $ROOT/grammars/$g.gm)
  learned=$(grep -cE '^(timesplit|animate)' t_${g}_l.gm)
  units=$(head -1 t_${g}_r.txt | sed 's/learned \([0-9]*\) units.*/\1/')
  bad=$(grep -c 'NOT EXPLAINED' t_${g}_r.txt)
  $G animate t_${g}_l.gm -o t_${g}_b.json >/dev/null 2>&1 || { echo "$g | animate of learned failed"; continue; }
  d=$(python3 -c "import json;d=json.load(open('t_$g.json'));print(d['op']-d['ip'], d['fr'])")
  n=$(echo $d | cut -d' ' -f1); fr=$(echo $d | cut -d' ' -f2)
  worst=0
  for k in 0 1 2 3 4 5 6 7 8 9; do
    t=$(python3 -c "print(round(($n-1)*$k/9)/$fr)")
    $G convert t_$g.json --time $t -o a_$g.png 2>/dev/null; $G convert t_${g}_b.json --time $t -o b_$g.png 2>/dev/null
    o=$(python3 -W ignore -c "
from PIL import Image, ImageChops
import numpy as np
a=np.array(Image.open('a_$g.png').convert('RGBA')).astype(int);b=np.array(Image.open('b_$g.png').convert('RGBA')).astype(int)
print(100*(np.abs(a-b).max(axis=2)>32).mean())")
    worst=$(python3 -c "print(max($worst,$o))")
  done
  printf "%s | %s | %s | %s | %s/%s | %.2f%% | %.2fs\n" $g $units $hand $learned $bad $units $worst $(python3 -c "print($e-$s)")
done
