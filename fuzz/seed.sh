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
# studio: one connection's requests, TOKEN and HOST standing for the session's (see
# fuzz_targets/studio.rs): polling, each route, an edit, pipelined requests, refusals.
studio_seed() { printf "$1" >/tmp/gmotion-seed.http; put studio /tmp/gmotion-seed.http; }
studio_seed 'GET /api/status HTTP/1.1\r\nHost: HOST\r\nX-Gmotion-Token: TOKEN\r\n\r\n'
studio_seed 'GET /api/state?token=TOKEN HTTP/1.1\r\nHost: HOST\r\n\r\nGET /api/boxes?t=0.5&token=TOKEN HTTP/1.1\r\nHost: HOST\r\n\r\n'
studio_seed 'GET /api/frame.png?t=0.4&w=32&seed=7&token=TOKEN HTTP/1.1\r\nHost: HOST\r\n\r\n'
studio_seed 'GET /api/rules?shape=0&t=0.2&token=TOKEN HTTP/1.1\r\nHost: HOST\r\n\r\nGET /api/lottie?token=TOKEN HTTP/1.0\r\nHost: HOST\r\n\r\n'
studio_seed 'PUT /api/grammar HTTP/1.1\r\nHost: HOST\r\nX-Gmotion-Token: TOKEN\r\nContent-Length: 29\r\n\r\nduration 1s\nfps 4\ntimesplit(1'
studio_seed 'POST /api/retime HTTP/1.1\r\nHost: HOST\r\nX-Gmotion-Token: TOKEN\r\nContent-Length: 40\r\n\r\n{"shape": 0, "boundary": 0, "time": 0.3}'
studio_seed 'POST /api/offset HTTP/1.1\r\nHost: HOST\r\nX-Gmotion-Token: TOKEN\r\nContent-Length: 50\r\n\r\n{"shape": 1, "slice": 0, "from": 0.1, "time": 0.2}'
studio_seed 'POST /api/value HTTP/1.1\r\nHost: HOST\r\nX-Gmotion-Token: TOKEN\r\nContent-Length: 39\r\n\r\n{"line": 4, "value": "translate(9, 0)"}'
studio_seed 'GET http://HOST/api/export/smil HTTP/1.1\r\nHost: x\r\nX-Gmotion-Token: TOKEN\r\nConnection: close\r\n\r\n'
studio_seed 'POST /api/save HTTP/1.1\r\nHost: HOST\r\nX-Gmotion-Token: TOKEN\r\nTransfer-Encoding: chunked\r\n\r\n0\r\n\r\n'
for t in grammar svg targets lottie export studio; do
    for f in fuzz/regressions/$t/*; do if [ -e "$f" ]; then put "$t" "$f"; fi; done
done
for t in grammar svg targets lottie export studio; do
    echo "fuzz/corpus/$t: $(ls "fuzz/corpus/$t" 2>/dev/null | wc -l) files"
done
