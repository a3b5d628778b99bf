"""crops.json as statfilter detect writes it, validated against the documented schema
(docs/crops.schema.json, described in docs/crops.md)."""

import json
import re
from pathlib import Path

import jsonschema
import pytest

from conftest import SAMPLE, run

DOCS = Path(__file__).resolve().parents[2] / "docs"
SCHEMA = json.loads((DOCS / "crops.schema.json").read_text())
NOISY = SAMPLE / "cornell_moving" / "spp0004" / "indirect.####.exr"


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    """The first 12 frames of the sample denoised (pca, rank 1), and what detect writes for them."""
    d = tmp_path_factory.mktemp("crops")
    run("denoise", NOISY, d / "den.####.exr", "--frames", "1-12", "--method", "pca", "--rank", "1", "--float", "-q")
    proc = run("detect", d / "den.####.exr", "--noisy", NOISY, "--frames", "1-12", "--crops", d / "crops.json", "--json")
    return (d / "crops.json").read_text(), proc.stdout, d


def test_detect_writes_what_the_schema_describes(written):
    text = written[0]
    doc = json.loads(text)
    jsonschema.Draft202012Validator.check_schema(SCHEMA)
    jsonschema.validate(doc, SCHEMA, cls=jsonschema.Draft202012Validator)
    assert doc["schema_version"] == 1 and doc["frame_count"] == 12
    assert doc["window_count"] > 0, "the test needs windows to check"


def test_members_mean_what_the_documentation_says(written):
    doc = json.loads(written[0])
    W, H = doc["width"], doc["height"]
    frames = [f["frame"] for f in doc["frames"]]
    assert frames == sorted(frames) and all(f["windows"] for f in doc["frames"])
    assert doc["window_count"] == sum(len(f["windows"]) for f in doc["frames"])
    assert doc["window_pixels"] == sum(w["width"] * w["height"] for f in doc["frames"] for w in f["windows"])
    assert doc["flagged_pixels"] == sum(f["flagged_pixels"] for f in doc["frames"])
    assert doc["window_fraction"] == pytest.approx(doc["window_pixels"] / (W * H * doc["frame_count"]))
    # render_frames: the listed frames as ranges.
    listed = []
    for part in doc["render_frames"].split(","):
        first, _, last = part.partition("-")
        listed += range(int(first), int(last or first) + 1)
    assert listed == frames
    # What a farm reads per frame: the frame's window count and pixels, each window's index (the
    # {window} of merge's file names), and the plan's cost with each start-up as window_cost pixels.
    assert doc["cost_pixels"] == doc["window_pixels"] + doc["window_count"] * doc["window_cost"]
    for f in doc["frames"]:
        assert f["window_count"] == len(f["windows"])
        assert f["window_pixels"] == sum(w["width"] * w["height"] for w in f["windows"])
        assert [w["index"] for w in f["windows"]] == list(range(len(f["windows"])))
        for w in f["windows"]:
            assert w["x"] + w["width"] <= W and w["y"] + w["height"] <= H
            # border: fractions of the frame, y up from the bottom (Blender's render border).
            assert w["border"] == pytest.approx([w["x"] / W, 1 - (w["y"] + w["height"]) / H,
                                                 (w["x"] + w["width"]) / W, 1 - w["y"] / H], abs=1e-12)


def test_every_member_of_the_schema_is_documented():
    text = (DOCS / "crops.md").read_text()
    names = set(SCHEMA["properties"]) | set(SCHEMA["properties"]["frames"]["items"]["properties"]) \
        | set(SCHEMA["$defs"]["window"]["properties"])
    for name in names:
        assert "`%s`" % name in text, name


def test_the_schema_refuses_what_merge_would_refuse(written):
    doc = json.loads(written[0])
    for broken in ({k: v for k, v in doc.items() if k != "schema_version"}, dict(doc, schema_version=2),
                   dict(doc, frames=[{"frame": 1, "windows": [{"x": -1, "y": 0, "width": 4, "height": 4}]}])):
        with pytest.raises(jsonschema.ValidationError):
            jsonschema.validate(broken, SCHEMA, cls=jsonschema.Draft202012Validator)


def test_library_and_cli_write_numbers_alike(written):
    """crops.json is written by the library (lib/json.cpp), --json by the CLI (tools/cli_json.hpp):
    the same double must come out as the same text."""
    text, report = written[0], written[1]

    def raw(document, name):
        return re.search(r'"%s": ([-0-9.eE+]+)' % name, document).group(1)
    for name in ("flagged_fraction", "window_fraction"):
        assert raw(text, name) == raw(report, name), name


def test_merge_refuses_an_unknown_schema_version_and_reads_the_former_version_member(written, tmp_path):
    doc, d = json.loads(written[0]), written[2]
    den = d / "den.####.exr"
    crops = tmp_path / "crops.json"
    crops.write_text(json.dumps(dict(doc, schema_version=2)))
    proc = run("merge", den, den, tmp_path / "m.####.exr", "--crops", crops, check_rc=1)
    assert "schema version 2 is not supported" in proc.stderr
    # Files written before the member was named schema_version.
    crops.write_text(json.dumps(dict({k: v for k, v in doc.items() if k != "schema_version"}, version=1)))
    run("merge", den, den, tmp_path / "m.####.exr", "--crops", crops, "--frames", "1-12", "-q")
    assert len(list(tmp_path.glob("m.*.exr"))) == 12
