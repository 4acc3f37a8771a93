"""Writes assets/l60mc.rbl, the Rerun blueprint of a chaindrive recording.

The blueprint opens a top-down 3D view of the drive (the sprocket outlines
turning in their frames, the rollers coloured by link force) beside plots of
the segments' mean link forces and the sprockets' speeds, picked out of the
protobuf messages of `/segments` and `/sprockets` by selectors.

It applies to recordings converted with the application id `chaindrive`:

    rerun mcap convert l60mc.mcap --timeline-type duration --application-id chaindrive -o l60mc.rrd
    rerun l60mc.rrd assets/l60mc.rbl

Regenerate it after changing this script (rerun-sdk 0.41):

    python3 assets/l60mc_blueprint.py assets/l60mc.rbl
"""

from __future__ import annotations

import sys

import rerun as rr
import rerun.blueprint as rrb
from rerun.blueprint.encodings import ComponentSourceKind, VisualizerComponentMapping

APPLICATION_ID = "chaindrive"
SEGMENTS = 4
SPROCKETS = 4


def series(source_component: str, selector: str, name: str) -> rrb.Visualizer:
    """One plotted line: the scalar `selector` picks out of `source_component`."""
    return rr.SeriesLines(names=[name]).visualizer(
        mappings=[
            VisualizerComponentMapping(
                target="Scalars:scalars",
                source_kind=ComponentSourceKind.SourceComponent,
                source_component=source_component,
                selector=selector,
            )
        ]
    )


def blueprint() -> rrb.Blueprint:
    segments = [
        series(
            "segmentsignals.SegmentSignals:message",
            f".segments[{k}].link_force_n",
            f"segment {k + 1} link force, N",
        )
        for k in range(SEGMENTS)
    ]
    speeds = [
        series(
            "sprocketsignals.SprocketSignals:message",
            f".speed_rad_s[{i}]",
            f"sprocket {i + 1} speed, rad/s",
        )
        for i in range(SPROCKETS)
    ]
    return rrb.Blueprint(
        rrb.Horizontal(
            rrb.Spatial3DView(
                name="drive",
                origin="/",
                contents=["/outlines/**", "/rollers", "/tf"],
            ),
            rrb.Vertical(
                rrb.TimeSeriesView(
                    name="segment link forces",
                    contents=["/segments"],
                    overrides={"/segments": segments},
                ),
                rrb.TimeSeriesView(
                    name="sprocket speeds",
                    contents=["/sprockets"],
                    overrides={"/sprockets": speeds},
                ),
            ),
            column_shares=[3, 2],
        ),
        collapse_panels=False,
    )


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "assets/l60mc.rbl"
    blueprint().save(APPLICATION_ID, out)
    print(f"wrote {out}")
