#!/usr/bin/env bash
# Fills fuzz/corpus/TARGET with seeds from the repository: the bundled grammars, scenes and
# targets files, the resvg test SVGs, the Lottie corpus (when tests/conformance/install.sh
# has fetched it), and every regression case. Existing corpus files are kept (a corpus
# grows across runs); seeds are named by content, so running this again adds nothing twice.
set -euo pipefail
cd "$(dirname "$0")/.."
put() { # put TARGET FILE [PREFIX-BYTE]
    local dir="fuzz/corpus/$1" sum
    mkdir -p "$dir"
    if [ $# -eq 3 ]; then
        sum=$( (printf "\\x$3"; cat "$2") | sha1sum | cut -c1-40)
        (printf "\\x$3"; cat "$2") >"$dir/seed-$sum"
    else
        sum=$(sha1sum <"$2" | cut -c1-40)
        cp "$2" "$dir/seed-$sum"
    fi
}
for f in grammars/*.gm grammars/bench/*.gm; do put grammar "$f"; done
for f in grammars/*.svg tests/corpus/resvg/*.svg; do put svg "$f"; done
for f in grammars/*.targets.json; do put targets "$f"; done
printf 'time,tag,id,attr,value\n0,box,0,rotate,30\n0.2,box,*,rotate,-45\n1,ball,0,x,3\n' >/tmp/gmotion-seed.csv
put targets /tmp/gmotion-seed.csv
for f in tests/conformance/lottie-corpus/*.json; do if [ -e "$f" ]; then put lottie "$f"; fi; done
# export: the scene's index byte (fuzz_targets/export.rs lists the scenes), then its grammar.
i=0
for name in toy leaf growing_tangle regroup cube variations priorities intersections_mini abstract panel; do
    put export "grammars/$name.gm" "$(printf %02x $i)"
    i=$((i + 1))
done
for t in grammar svg targets lottie export; do
    for f in fuzz/regressions/$t/*; do if [ -e "$f" ]; then put "$t" "$f"; fi; done
done
for t in grammar svg targets lottie export; do
    echo "fuzz/corpus/$t: $(ls "fuzz/corpus/$t" 2>/dev/null | wc -l) files"
done
