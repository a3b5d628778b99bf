"""The re-render hand-off scripts (scripts/handoff/): the coordinates they give each renderer, and a
real Blender render of crop windows when a Python with ``bpy`` is at hand.

Blender: this interpreter if it imports bpy, else the one STATFILTER_BPY_PYTHON names (bpy from PyPI
is a ~370 MB wheel that pins numpy < 2, so setup.sh does not install it; docs/rerender.md says how to
make such a venv). Without either the Blender tests skip; the coordinate tests always run.
"""

import importlib.util
import json
import os
import random
import shutil
import struct
import subprocess
import sys

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
HANDOFF = os.path.join(ROOT, "scripts", "handoff")
sys.path.insert(0, HANDOFF)

import blender_render_crops as brc  # noqa: E402
import crops_to_commands as ctc  # noqa: E402

W, H = 64, 48
CROPS = {"format": "statfilter-crops", "schema_version": 1, "width": W, "height": H, "frame_count": 2, "frames": [
    {"frame": 1, "windows": [{"x": 5, "y": 4, "width": 20, "height": 12}, {"x": 40, "y": 30, "width": 16, "height": 10}]},
    {"frame": 2, "windows": [{"x": 10, "y": 20, "width": 30, "height": 20}]},
]}


def random_windows(rng, width, height, n):
    out = []
    for _ in range(n):
        w, h = rng.randint(1, width), rng.randint(1, height)
        out.append({"x": rng.randint(0, width - w), "y": rng.randint(0, height - h), "width": w, "height": h})
    return out


# --- coordinates, checked against each renderer's own rounding rule -----------------------------

def test_blender_border_flips_y_and_truncates_to_the_window():
    # Window y 4..15 (from the top) of 48 rows is Blender rows 32..43 from the bottom.
    b = brc.blender_border({"x": 5, "y": 4, "width": 20, "height": 12}, W, H)
    assert b == pytest.approx((5.5 / 64, 32.5 / 48, 25.5 / 64, 44.5 / 48))
    # Blender's pixels: int(border x size) for each edge (float32, as RNA stores it).
    rng = random.Random(3)
    for width, height in [(64, 48), (1920, 1080), (2048, 858), (7, 5), (4096, 2160)]:
        for w in random_windows(rng, width, height, 300):
            mn_x, mn_y, mx_x, mx_y = (float(np.float32(v)) for v in brc.blender_border(w, width, height))
            x0, x1 = int(np.float32(mn_x) * np.float32(width)), int(np.float32(mx_x) * np.float32(width))
            y0, y1 = int(np.float32(mn_y) * np.float32(height)), int(np.float32(mx_y) * np.float32(height))
            assert (x0, x1) == (w["x"], w["x"] + w["width"]), (width, w)
            # Bottom-up rows y0 .. y1 - 1 are top-down rows height - y1 .. height - y0 - 1.
            assert (height - y1, height - y0) == (w["y"], w["y"] + w["height"]), (height, w)


def test_renderman_crop_window_selects_exactly_the_window():
    # The RenderMan Interface's rule: pixels ceil(res * min) .. ceil(res * max - 1), clamped.
    rng = random.Random(5)
    for width, height in [(64, 48), (1920, 1080), (2048, 858), (7, 5)]:
        for w in random_windows(rng, width, height, 300):
            xmin, xmax, ymin, ymax = (float("%.9g" % v) for v in ctc.renderman_crop(w, width, height))
            clamp = lambda v, n: min(max(v, 0), n - 1)  # noqa: E731
            rx = (clamp(int(np.ceil(width * xmin)), width), clamp(int(np.ceil(width * xmax - 1)), width))
            ry = (clamp(int(np.ceil(height * ymin)), height), clamp(int(np.ceil(height * ymax - 1)), height))
            assert rx == (w["x"], w["x"] + w["width"] - 1), (width, w)
            assert ry == (w["y"], w["y"] + w["height"] - 1), (height, w)


def test_arnold_and_renderman_lines_have_the_known_numbers(tmp_path):
    path = tmp_path / "crops.json"
    path.write_text(json.dumps(CROPS))
    arnold = ctc.commands(str(path), "arnold", "shot.####.ass", "rr.{window}.####.exr")
    assert arnold == [
        "kick -i shot.0001.ass -rg 5 4 24 15 -o rr.0.0001.exr -dw -dp",
        "kick -i shot.0001.ass -rg 40 30 55 39 -o rr.1.0001.exr -dw -dp",
        "kick -i shot.0002.ass -rg 10 20 39 39 -o rr.0.0002.exr -dw -dp",
    ]
    rib = ctc.commands(str(path), "renderman", "shot.####.rib", "rr.{window}.%04d.exr", frames={2})
    assert rib == ['Display "rr.0.0002.exr" "openexr" "rgba" CropWindow 0.1484375 0.6171875 0.40625 0.822916667'
                   '  # frame 2 window 0: before WorldBegin of shot.0002.rib']
    # As a program: the same lines, and a clear error for a file that is not crops.json.
    out = subprocess.run([sys.executable, os.path.join(HANDOFF, "crops_to_commands.py"), str(path), "arnold",
                          "--scene", "shot.####.ass", "--out", "rr.{window}.####.exr", "--frames", "1"],
                         capture_output=True, text=True, check=True).stdout
    assert out.splitlines() == arnold[:2]
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": "something else"}')
    r = subprocess.run([sys.executable, os.path.join(HANDOFF, "crops_to_commands.py"), str(bad), "arnold",
                        "--scene", "s.ass", "--out", "o.####.exr"], capture_output=True, text=True)
    assert r.returncode == 2 and "not a statfilter crop-window file" in r.stderr


def test_patterns_frames_and_refusals():
    assert brc.output_path("rr.{window}.####.exr", 7, 2) == "rr.2.0007.exr"
    assert brc.output_path("out/rr_%04d_{window}.exr", 12, 0) == "out/rr_0012_0.exr"
    assert brc.parse_frames("3-5,9") == {3, 4, 5, 9}
    with pytest.raises(brc.CropsError):
        brc.output_path("rr.exr", 1, 0)
    with pytest.raises(brc.CropsError, match="schema version 2"):
        brc.load_crops(dict(CROPS, schema_version=2))
    with pytest.raises(brc.CropsError, match="outside"):
        brc.windows_by_frame(dict(CROPS, frames=[{"frame": 1, "windows": [{"x": 60, "y": 0, "width": 5, "height": 1}]}]))


# --- a real Blender render -------------------------------------------------------------------

def bpy_python():
    if importlib.util.find_spec("bpy") is not None:
        return sys.executable
    return os.environ.get("STATFILTER_BPY_PYTHON") or None


def blender_env():
    """The environment for Blender: without a sanitizer runtime preloaded for the statfilter library."""
    return {k: v for k, v in os.environ.items() if k not in ("LD_PRELOAD", "ASAN_OPTIONS")}


def exr_windows(path):
    """(dataWindow, displayWindow) of an EXR file, each (xmin, ymin, xmax, ymax), from its header."""
    with open(path, "rb") as f:
        data = f.read(65536)
    assert data[:4] == b"\x76\x2f\x31\x01", "%s is not an OpenEXR file" % path
    pos, found = 8, {}
    while data[pos] != 0:
        name_end = data.index(b"\0", pos)
        type_end = data.index(b"\0", name_end + 1)
        name, kind = data[pos:name_end].decode(), data[name_end + 1:type_end].decode()
        (size,) = struct.unpack_from("<i", data, type_end + 1)
        value = data[type_end + 5:type_end + 5 + size]
        if kind == "box2i":
            found[name] = struct.unpack("<4i", value)
        pos = type_end + 5 + size
    return found["dataWindow"], found["displayWindow"]


@pytest.fixture(scope="module")
def blender_scene(tmp_path_factory):
    python = bpy_python()
    if python is None:
        pytest.skip("no Python with bpy (pip install bpy in a Python 3.11 venv, then STATFILTER_BPY_PYTHON=its python)")
    d = tmp_path_factory.mktemp("blender")
    scene = d / "scene.blend"
    subprocess.run([python, os.path.join(HERE, "make_scene.py"), str(scene), str(W), str(H)], check=True,
                   capture_output=True, env=blender_env())
    # The reference: both frames rendered whole, by the same script with one window of the whole frame.
    whole = dict(CROPS, frames=[{"frame": f, "windows": [{"x": 0, "y": 0, "width": W, "height": H}]} for f in (1, 2)])
    (d / "whole.json").write_text(json.dumps(whole))
    run_blender_script(python, d / "whole.json", d / "full.####.exr", scene)
    (d / "crops.json").write_text(json.dumps(CROPS))
    return python, d, scene


def run_blender_script(python, crops, pattern, scene, *extra):
    return subprocess.run([python, os.path.join(HANDOFF, "blender_render_crops.py"), "--", str(crops), str(pattern),
                           "--blend", str(scene), *extra], check=True, capture_output=True, text=True,
                          env=blender_env())


def read(path):
    import statfilter

    return statfilter.read_sequence(str(path))


def test_blender_renders_each_window_as_a_window_sized_exr(blender_scene):
    python, d, scene = blender_scene
    out = d / "rr"
    r = run_blender_script(python, d / "crops.json", out / "rr.{window}.####.exr", scene)
    assert "3 window renders written" in r.stdout
    full = {f: read(d / ("full.%04d.exr" % f))[0] for f in (1, 2)}
    for entry in CROPS["frames"]:
        for k, w in enumerate(entry["windows"]):
            path = out / ("rr.%d.%04d.exr" % (k, entry["frame"]))
            data_window, display_window = exr_windows(path)
            assert data_window == (0, 0, w["width"] - 1, w["height"] - 1), path
            assert display_window == data_window
            # The same pixels as the whole frame's render there (Cycles seeds by pixel): a window
            # upside down, shifted or from another frame would differ.
            part = read(path)[0]
            expected = full[entry["frame"]][w["y"]:w["y"] + w["height"], w["x"]:w["x"] + w["width"]]
            np.testing.assert_allclose(part, expected, rtol=1e-5, atol=1e-6)
            flipped = full[entry["frame"]][H - w["y"] - w["height"]:H - w["y"], w["x"]:w["x"] + w["width"]]
            assert np.abs(part - flipped).max() > 1e-3, "the scene cannot tell the flip apart"


def test_blender_full_frame_and_one_frame_then_statfilter_merge(blender_scene, tmp_path):
    cli = os.environ.get("STATFILTER_CLI")
    python, d, scene = blender_scene
    r = run_blender_script(python, d / "crops.json", tmp_path / "ff.{window}.####.exr", scene, "--full-frame", "--frames", "1")
    assert "2 window renders written" in r.stdout
    assert not (tmp_path / "ff.0.0002.exr").exists()
    assert exr_windows(tmp_path / "ff.1.0001.exr")[0] == (0, 0, W - 1, H - 1)
    if not cli:
        pytest.skip("STATFILTER_CLI not set: the merge half needs the CLI")
    import statfilter

    # Merge the window renders into blank frames: the windows come back where they belong.
    out = tmp_path / "rr"
    run_blender_script(python, d / "crops.json", out / "rr.{window}.####.exr", scene)
    blank = np.zeros((2, H, W, 4), np.float32)
    statfilter.write_sequence(str(tmp_path / "blank.####.exr"), blank, pixel_type="float")
    subprocess.run([cli, "merge", str(tmp_path / "blank.####.exr"), str(out / "rr.{window}.####.exr"),
                    str(tmp_path / "merged.####.exr"), "--crops", str(d / "crops.json")], check=True, capture_output=True)
    merged = statfilter.read_sequence(str(tmp_path / "merged.####.exr"))
    for i, entry in enumerate(CROPS["frames"]):
        full = read(d / ("full.%04d.exr" % entry["frame"]))[0]
        inside = np.zeros((H, W), bool)
        for w in entry["windows"]:
            inside[w["y"]:w["y"] + w["height"], w["x"]:w["x"] + w["width"]] = True
        np.testing.assert_allclose(merged[i][inside], full[inside], rtol=1e-3, atol=1e-3)
        assert np.all(merged[i][~inside] == 0)
