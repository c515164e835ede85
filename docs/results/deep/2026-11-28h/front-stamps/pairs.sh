#!/bin/bash
# pairs.sh A B N SCENES...: N interleaved pairs of the tools ./A and ./B (built with
# frame-stamps.diff), orbiting, the order alternating pair by pair; logs A-SCENE-I.txt, results out-A-SCENE-I/.
a=$1; b=$2; n=$3; shift 3
for i in $(seq 1 $n); do for s in "$@"; do
  if [ $((i%2)) = 1 ]; then order="$a $b"; else order="$b $a"; fi
  for v in $order; do
    echo "$(date +%T) $(cut -d' ' -f1-3 /proc/loadavg) $v $s $i" >> log.txt
    ES_STAMPS=1 ./$v bench --quick --frames 15 --orbit 0.5 --scenes $s --methods impostor-visible-first --out out-$v-$s-$i > $v-$s-$i.txt 2>&1
  done
done; done
