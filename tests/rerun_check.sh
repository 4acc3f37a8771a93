#!/usr/bin/env bash
# Rerun check: a recording of the paper's drive converts with Rerun's own
# `rerun mcap convert`, and the .rrd holds what a user sees and plots.
#
# It runs the README's Rerun recipe (the commands between the markers
# `rerun-recipe:begin` and `rerun-recipe:end` in README.md) as written, in a
# scratch directory, with the `rerun` CLI of the pip package `rerun-sdk` and
# this checkout's release `chaindrive` on the PATH. Then it reads the .rrd
# with the Python SDK, prints the archetypes of every entity, and fails unless
#   - /outlines/sprocket1..4 hold Points3D in coordinate frames sprocket1..4,
#     and /tf holds Transform3D from `world` to each of those frames;
#   - /rollers holds Points3D with colours;
#   - the selectors of assets/l60mc_blueprint.py pick finite numbers out of
#     /segments and /sprockets (what the blueprint's plots show);
#   - assets/l60mc_blueprint.py still writes a blueprint.
#
# The virtual environment is created once and kept under target/ (override
# with RERUN_VENV=dir). Usage: bash tests/rerun_check.sh
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
venv=${RERUN_VENV:-$root/target/rerun-venv}
rerun_version='0.41.*'

if [[ ! -x $venv/bin/rerun ]]; then
    python3 -m venv "$venv"
    "$venv/bin/pip" install --quiet "rerun-sdk==$rerun_version"
fi
"$venv/bin/python" -c 'import rerun; print("rerun-sdk", rerun.__version__)'

cargo build --release --quiet --bin chaindrive

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
recipe=$(sed -n '/rerun-recipe:begin/,/rerun-recipe:end/p' README.md | sed '/^```/d;/rerun-recipe:/d')
if [[ -z $recipe ]]; then
    echo "README.md has no Rerun recipe between rerun-recipe:begin and rerun-recipe:end" >&2
    exit 1
fi
echo "--- the README's recipe:"
echo "$recipe"
echo "---"
(
    cd "$work"
    export PATH="$root/target/release:$venv/bin:$PATH"
    set -x
    eval "$recipe"
) > "$work/recipe.log" 2>&1 || {
    cat "$work/recipe.log"
    echo "the README's Rerun recipe failed" >&2
    exit 1
}
awk '/Points3D|Transform3D/ && n++ < 6' "$work/recipe.log"

"$venv/bin/python" "$root/assets/l60mc_blueprint.py" "$work/check.rbl"

"$venv/bin/python" - "$work/l60mc.rrd" "$root/assets/l60mc.rbl" <<'EOF'
import math
import sys
from collections import defaultdict

import pyarrow as pa
import rerun as rr

path = sys.argv[1]
chunks = rr.chunk.RrdReader(path).stream().to_chunks()
archetypes = defaultdict(set)
columns = defaultdict(lambda: defaultdict(list))
for chunk in chunks:
    batch = chunk.to_record_batch()
    for field, column in zip(batch.schema, batch.columns):
        meta = field.metadata or {}
        name = (meta.get(b"rerun:component") or field.name.encode()).decode()
        if ":" not in name:
            continue
        archetypes[chunk.entity_path].add(name.split(":")[0])
        columns[chunk.entity_path][name].append(column)

print("archetypes per entity:")
for entity in sorted(archetypes):
    print(f"  {entity}: {', '.join(sorted(archetypes[entity]))}")

failures = []


def need(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        failures.append(what)


def values(entity, component):
    """Every row of a component, flattened one level (a row holds a list)."""
    out = []
    for column in columns[entity].get(component, []):
        out.extend(column.to_pylist())
    return out


child_frames = {
    f for row in values("/tf", "Transform3D:child_frame") for f in (row or [])
}
parent_frames = {
    f for row in values("/tf", "Transform3D:parent_frame") for f in (row or [])
}
need("Transform3D" in archetypes["/tf"], "/tf holds Transform3D")
need(parent_frames == {"world"}, f"/tf parent frames {sorted(parent_frames)} are world")
for i in range(1, 5):
    entity = f"/outlines/sprocket{i}"
    need("Points3D" in archetypes[entity], f"{entity} holds Points3D")
    frames = {f for row in values(entity, "CoordinateFrame:frame") for f in (row or [])}
    need(frames == {f"sprocket{i}"}, f"{entity} is in frame sprocket{i} (found {sorted(frames)})")
    need(f"sprocket{i}" in child_frames, f"/tf moves frame sprocket{i}")
    points = [p for row in values(entity, "Points3D:positions") for p in (row or [])]
    need(len(points) > 500, f"{entity}: {len(points)} outline points")
need("Points3D" in archetypes["/rollers"], "/rollers holds Points3D")
colors = {c for row in values("/rollers", "Points3D:colors") for c in (row or [])}
need(len(colors) > 1, f"/rollers: {len(colors)} distinct colours")

# The shipped blueprint's plots: every (component, selector) it maps to a
# plotted scalar must give numbers on this recording.
blueprint = rr.chunk.RrdReader(sys.argv[2])
stores = blueprint.blueprints()
need(
    [s.application_id for s in stores] == ["chaindrive"],
    f"{sys.argv[2]}: one blueprint for application id chaindrive",
)
plots = set()
for chunk in blueprint.stream(store=stores[0]).to_chunks() if stores else []:
    batch = chunk.to_record_batch()
    for field, column in zip(batch.schema, batch.columns):
        kind = (field.metadata or {}).get(b"rerun:component_type", b"")
        if b"VisualizerComponentMapping" not in kind:
            continue
        for row in column.to_pylist():
            for mappings in row or []:
                for m in mappings if isinstance(mappings, list) else [mappings]:
                    plots.add((m["source_component"], m["selector"]))
need(len(plots) == 8, f"the blueprint plots {len(plots)} selected scalars")
entity_of = {
    component: entity
    for entity, components in columns.items()
    for component in components
}
for component, query in sorted(plots):
    entity = entity_of.get(component, "(none)")
    selector = rr.chunk.Selector(query)
    numbers = []
    for column in columns[entity].get(component, []):
        flat = column.flatten() if pa.types.is_list(column.type) else column
        result = selector.execute(flat)
        if result is not None:
            numbers.extend(v for v in result.to_pylist() if v is not None)
    finite = [v for v in numbers if isinstance(v, float) and math.isfinite(v)]
    need(len(finite) > 100, f"{entity} {query}: {len(finite)} finite values to plot")
    if finite:
        print(f"      e.g. {finite[len(finite) // 2]:.1f} at mid-run")

if failures:
    print(f"{len(failures)} check(s) failed", file=sys.stderr)
    sys.exit(1)
print("rerun check passed")
EOF
