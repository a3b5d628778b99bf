"""EXR layouts through the CLI: region renders keep their windows, auto-cropped frames are read on
the display window, several layers keep their names, info shows the default selection. The
inputs are written here with oiiotool."""
import json
import subprocess

from conftest import oiio_tool, run

LAYERS = ["ViewLayer.Diffuse Direct", "ViewLayer.Diffuse Indirect"]


def oiiotool(*args):
    subprocess.run([oiio_tool("oiiotool"), *map(str, args)], check=True, capture_output=True)


def header(path):
    return subprocess.run([oiio_tool("oiiotool"), "--info", "-v", str(path)], check=True, capture_output=True,
                          text=True).stdout


def channel_list(path):
    line = [line for line in header(path).splitlines() if "channel list" in line][0]
    return line.split(":", 1)[1].strip().split(", ")


def test_region_keeps_its_windows_through_denoise(tmp_path):
    for f in (1, 2):
        oiiotool("--create", "160x120", "3", "--fill:color=0.5,0.2,0.%d" % f, "160x120", "--crop", "150x120+5+0",
                 "-o", tmp_path / ("region.%04d.exr" % f))
    info = json.loads(run("info", tmp_path / "region.####.exr", "--json").stdout)
    assert info["data_window"] == {"x": 5, "y": 0, "width": 150, "height": 120}
    assert info["display_window"] == {"x": 0, "y": 0, "width": 160, "height": 120}
    run("denoise", tmp_path / "region.####.exr", tmp_path / "out" / "copy.####.exr", "--method", "copy", "--float",
        "-q")
    text = header(tmp_path / "out" / "copy.0002.exr")
    assert "150 x  120" in text and "pixel data origin: x=5, y=0" in text and "full/display size: 160 x 120" in text
    subprocess.run([oiio_tool("idiff"), tmp_path / "region.0002.exr", tmp_path / "out" / "copy.0002.exr"], check=True,
                   capture_output=True)


def test_auto_cropped_frames_are_read_on_the_display_window(tmp_path):
    oiiotool("--create", "40x30", "3", "--fill:color=1,1,1", "40x30", "-o", tmp_path / "crop.0001.exr")
    oiiotool("--create", "40x30", "3", "--fill:color=1,1,1", "40x30", "--crop", "20x10+3+4",
             "-o", tmp_path / "crop.0002.exr")
    out = run("info", tmp_path / "crop.####.exr", "-q").stdout
    assert "size      40 x 30" in out and "cropped   frames 2" in out and "0 outside" in out
    run("denoise", tmp_path / "crop.####.exr", tmp_path / "full.####.exr", "--method", "copy", "--float", "-q")
    text = header(tmp_path / "full.0002.exr")
    assert "40 x   30" in text
    stats = subprocess.run([oiio_tool("oiiotool"), "--stats", tmp_path / "full.0002.exr"], check=True,
                           capture_output=True, text=True).stdout
    assert "Min: 0.000000 0.000000 0.000000" in stats and "Max: 1.000000 1.000000 1.000000" in stats


def test_several_layers_keep_their_names_and_the_default_leaves_data_passes(tmp_path):
    names = [f"{layer}.{c}" for layer in LAYERS for c in "RGB"] + ["ViewLayer.Normal.X", "ViewLayer.Combined.A"]
    oiiotool("--create", "8x6", str(len(names)), "--chnames", ",".join(names), "-o", tmp_path / "aov.0001.exr")
    out = run("info", tmp_path / "aov.0001.exr", "-q").stdout
    assert "default   ViewLayer.Diffuse Direct.{R,G,B} ViewLayer.Diffuse Indirect.{R,G,B}" in out
    assert "ViewLayer.Normal.X" in out  # info shows every channel
    run("denoise", tmp_path / "aov.0001.exr", tmp_path / "two.0001.exr", "--method", "copy",
        "--channels", ",".join(reversed(LAYERS)), "-q")
    assert sorted(channel_list(tmp_path / "two.0001.exr")) == sorted(names[:6])
    run("denoise", tmp_path / "aov.0001.exr", tmp_path / "default.0001.exr", "--method", "copy", "-q")
    assert sorted(channel_list(tmp_path / "default.0001.exr")) == sorted(names[:6])


def test_tiled_output_on_request(tmp_path):
    oiiotool("--create", "40x30", "3", "--fill:color=0.5,0.5,0.5", "40x30", "-o", tmp_path / "in.0001.exr")
    run("denoise", tmp_path / "in.0001.exr", tmp_path / "tiled.0001.exr", "--method", "copy", "--tiled", "16", "-q")
    assert "tile size: 16 x 16" in header(tmp_path / "tiled.0001.exr")
    bad = run("denoise", tmp_path / "in.0001.exr", tmp_path / "bad.0001.exr", "--method", "copy", "--tiled", "x",
              check_rc=2)
    assert "--tiled" in bad.stderr


def two_part_frames(tmp_path, frames=3):
    """Frames of two parts: the light pass, then normals (which a renderer's compositor still needs)."""
    light = ",".join(f"{LAYERS[1]}.{c}" for c in "RGB")
    for f in range(1, frames + 1):
        oiiotool("--create", "32x24", "3", "--fill:color=0.5,0.2,0.%d" % f, "32x24", "--attrib", "cycles.samples", "16",
                 "--chnames", light, "-o", tmp_path / "light.exr")
        oiiotool("--create", "32x24", "3", "--fill:color=0.1,0.9,0.%d" % f, "32x24",
                 "--chnames", "ViewLayer.Normal.X,ViewLayer.Normal.Y,ViewLayer.Normal.Z", "-o", tmp_path / "normal.exr")
        oiiotool(tmp_path / "light.exr", tmp_path / "normal.exr", "--siappend", "-o", tmp_path / ("in.%04d.exr" % f))
    return tmp_path / "in.####.exr"


def test_into_writes_the_light_back_beside_the_untouched_parts(tmp_path):
    pattern = two_part_frames(tmp_path)
    run("denoise", pattern, "--into", tmp_path / "out" / "into.####.exr", "--method", "pca", "--rank", "1", "-q")
    text = subprocess.run([oiio_tool("oiiotool"), "--info", "-v", "-a", tmp_path / "out" / "into.0002.exr"],
                          check=True, capture_output=True, text=True).stdout
    assert "2 subimages" in text and "cycles.samples: 16" in text and 'statfilter:filter: "pca"' in text
    assert "ViewLayer.Normal.X" in text
    same = subprocess.run([oiio_tool("oiiotool"), "-a", tmp_path / "in.0002.exr", "--subimage", "1",
                           tmp_path / "out" / "into.0002.exr", "--subimage", "1", "--diff"],
                          capture_output=True, text=True)
    assert same.returncode == 0 and "PASS" in same.stdout, same.stdout + same.stderr


def test_into_refuses_what_it_cannot_honour(tmp_path):
    pattern = two_part_frames(tmp_path, frames=2)
    out = tmp_path / "out" / "into.####.exr"
    for extra, words in ((["--float"], "--float does not apply"), (["--tiled", "16"], "--tiled does not apply"),
                         ([tmp_path / "o.####.exr"], "give only IN")):
        bad = run("denoise", pattern, "--into", out, "--method", "copy", *extra, check_rc=2)
        assert words in bad.stderr, bad.stderr
    assert not (tmp_path / "out").exists()
