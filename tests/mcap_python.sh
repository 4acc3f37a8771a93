#!/usr/bin/env bash
# Recordings open in Python's `mcap` package (the seeking reader Foxglove's
# tools use): a finished recording, and one killed with SIGKILL then passed
# through `chaindrive recover`. Each must yield messages through
# `make_reader(f).iter_messages()` and carry a summary with its chunk index.
# The killed file itself must not (that is what `recover` is for).
#
#   bash tests/mcap_python.sh [BINARY]
#
# Creates (once) a virtual environment with `mcap` under
# ${XDG_CACHE_HOME:-~/.cache}/chaindrive/mcap-venv; needs `python3 -m venv`
# and, the first time, network access for `pip`. Takes about 10 s once the
# environment exists (about 40 s the first time).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-target/release/chaindrive}
venv=${XDG_CACHE_HOME:-$HOME/.cache}/chaindrive/mcap-venv
if ! "$venv/bin/python" -c 'import mcap' 2>/dev/null; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet mcap
fi
dir=$(mktemp -d)
child=
cleanup() {
  [[ -n $child ]] && kill -KILL "$child" 2>/dev/null || true
  rm -rf "$dir"
}
trap cleanup EXIT

# A finished recording.
"$bin" run --quiet --duration 0.3 --record "$dir/done.mcap" >/dev/null

# A recording killed with SIGKILL once it holds a few chunks.
"$bin" run --quiet --duration 60 --record "$dir/killed.mcap" >/dev/null 2>&1 &
child=$!
for _ in $(seq 1 600); do
  size=$(stat -c %s "$dir/killed.mcap" 2>/dev/null || echo 0)
  ((size > 3 * 1024 * 1024)) && break
  sleep 0.1
done
kill -KILL "$child"
wait "$child" 2>/dev/null || true
child=
"$bin" recover "$dir/killed.mcap" "$dir/recovered.mcap" >/dev/null

"$venv/bin/python" - "$dir" <<'PY'
import sys
from mcap.reader import make_reader

d = sys.argv[1]

def read(name):
    with open(f"{d}/{name}", "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        count = sum(1 for _ in reader.iter_messages())
    return summary, count

for name in ("done.mcap", "recovered.mcap"):
    summary, count = read(name)
    assert summary is not None, f"{name}: no summary"
    assert summary.chunk_indexes, f"{name}: no chunk index"
    assert summary.statistics is not None, f"{name}: no statistics"
    assert count > 0, f"{name}: no messages"
    assert count == summary.statistics.message_count, (name, count, summary.statistics.message_count)
    print(f"{name}: {count} messages, {len(summary.chunk_indexes)} chunks indexed")

# The killed file is what the viewers refused: no summary to seek by.
try:
    summary, count = read("killed.mcap")
except Exception as e:  # the seeking reader gives up on a file without a footer
    print(f"killed.mcap: refused as expected ({type(e).__name__})")
else:
    assert summary is None or count == 0, "a killed recording reads whole without recovery"
    print(f"killed.mcap: {count} messages through the seeking reader, as expected")
PY
echo "mcap_python: ok"
