"""The renderer's passes from a multilayer EXR (the light and every data pass in one file, as Cycles
writes it): --albedo, --normal and --vectors given the shot's own files take the layer named for
the pass, or given a layer's name take that layer of the input's files, and give what the pass's
own files give, in a run and in a plan; a file with layers but none for the pass, or several, is
refused naming its layers. The files are written here with oiiotool from the sample."""
import json
import subprocess

import pytest

from conftest import SAMPLE, oiio_tool, run

FRAMES = range(1, 33)
AUX = SAMPLE / "cornell_moving" / "aux"
NOISY = SAMPLE / "cornell_moving" / "spp0004"


def oiiotool(*args):
    subprocess.run([oiio_tool("oiiotool"), *map(str, args)], check=True, capture_output=True)


def vectors_file(path):
    """A Vector pass of its own (X, Y, Z, W): half a pixel right each frame, a quarter up."""
    oiiotool("--create", "160x120", "4", "--fill:color=0.5,0.25,0.5,0.25", "160x120", "--chnames", "X,Y,Z,W",
             "-d", "float", "-o", path)


def multilayer_shot(d, layers=("Combined", "DiffCol", "Normal", "Vector")):
    """Frames holding the sample's light, albedo and normal, and vectors, each as a layer of
    ViewLayer (and, with "Other.Vector", a second view layer's vectors)."""
    d.mkdir(exist_ok=True)
    for f in FRAMES:
        parts = []
        for layer in layers:
            if layer == "RGB":  # another renderer's beauty: plain R, G, B beside layers
                parts += [NOISY / f"indirect.{f:04d}.exr", "--chnames", "R,G,B"]
            elif layer == "albedo":
                parts += [AUX / f"albedo.{f:04d}.exr", "--chnames", "albedo.R,albedo.G,albedo.B"]
            elif layer == "Combined":
                parts += [NOISY / f"indirect.{f:04d}.exr", "--chnames", "ViewLayer.Combined.R,ViewLayer.Combined.G,ViewLayer.Combined.B"]
            elif layer == "DiffCol":
                parts += [AUX / f"albedo.{f:04d}.exr", "--chnames", "ViewLayer.DiffCol.R,ViewLayer.DiffCol.G,ViewLayer.DiffCol.B"]
            elif layer == "Normal":
                parts += [AUX / f"normal.{f:04d}.exr", "--chnames", "ViewLayer.Normal.X,ViewLayer.Normal.Y,ViewLayer.Normal.Z"]
            else:
                vectors_file(d / "v.exr")
                prefix = {"Other.Vector": "Other.", "Vector": "ViewLayer.", "bare Vector": ""}[layer]
                parts += [d / "v.exr", "--chnames", ",".join(f"{prefix}Vector.{c}" for c in "XYZW")]
        args = parts[:3]
        for i in range(3, len(parts), 3):
            args += parts[i:i + 3] + ["--chappend"]
        oiiotool(*args, "-d", "float", "-o", d / f"shot.{f:04d}.exr")
    return d / "shot.####.exr"


@pytest.fixture(scope="module")
def shot(tmp_path_factory):
    return multilayer_shot(tmp_path_factory.mktemp("multilayer"))


def rel_mse(a, b):
    return json.loads(run("compare", a, b, "--json").stdout)["rel_mse"]


def assert_same_output(tmp_path, options, own, layered, label="layers"):
    """The sample with the passes' own files (own: their options), and the multilayer shot (layered:
    its input, channels and pass options): the same frames, to the bit. Returns both runs."""
    own_run = run("denoise", NOISY / "indirect.####.exr", tmp_path / "own" / "o.####.exr", *options, *own)
    layered_run = run("denoise", *layered[:1], tmp_path / label / "o.####.exr", *options, *layered[1:])
    assert rel_mse(tmp_path / label / "o.####.exr", tmp_path / "own" / "o.####.exr") == 0
    return own_run, layered_run


def test_albedo_and_normal_layers_give_what_their_own_files_give(tmp_path, shot):
    options = ["--method", "hybrid", "--mc_half_width", "2", "--float", "--quiet"]
    own = ["--albedo", AUX / "albedo.####.exr", "--normal", AUX / "normal.####.exr"]
    assert_same_output(tmp_path, options, own, [shot, "--channels", "ViewLayer.Combined", "--albedo", shot, "--normal", shot])
    run("denoise", shot, tmp_path / "named" / "o.####.exr", *options, "--channels", "ViewLayer.Combined",
        "--albedo", "ViewLayer.DiffCol", "--normal", "ViewLayer.Normal")
    assert rel_mse(tmp_path / "named" / "o.####.exr", tmp_path / "own" / "o.####.exr") == 0
    # Without the passes the output is another: they were read, not passed over.
    run("denoise", NOISY / "indirect.####.exr", tmp_path / "none" / "o.####.exr", *options)
    assert rel_mse(tmp_path / "none" / "o.####.exr", tmp_path / "own" / "o.####.exr") > 0


def test_the_vector_layer_gives_what_its_own_files_give(tmp_path, shot):
    for f in FRAMES:
        vectors_file(tmp_path / f"vector.{f:04d}.exr")
    options = ["--quality", "balanced", "--float", "--quiet"]
    for proc in assert_same_output(tmp_path, options + ["--json"], ["--vectors", tmp_path / "vector.####.exr"],
                                   [shot, "--channels", "ViewLayer.Combined", "--vectors", shot]):
        assert json.loads(proc.stdout)["results"]["hybrid.motion_compensation"] == "the renderer's motion vectors"

    # The layer by name, in a plan: the tasks read it from the input's files.
    plan = tmp_path / "plan.json"
    run("plan", shot, tmp_path / "farm" / "o.####.exr", *options, "--channels", "ViewLayer.Combined",
        "--vectors", "ViewLayer.Vector", "-o", plan)
    written = json.loads(plan.read_text())
    assert written["kind"] == "window" and written["version"] == 2
    assert written["front_end"]["inputs"] == {"vectors": "ViewLayer.Vector"}
    for task in written["tasks"]:
        run("task", plan, task["index"], "--quiet")
    assert rel_mse(tmp_path / "farm" / "o.####.exr", tmp_path / "own" / "o.####.exr") == 0


def test_layers_beside_channels_of_no_layer(tmp_path):
    """Plain R, G, B (the beauty, as other renderers keep it) beside layers of data passes: the passes
    are still their layers, not the whole file."""
    shot = multilayer_shot(tmp_path / "shot", ("RGB", "bare Vector", "albedo"))
    for f in FRAMES:
        vectors_file(tmp_path / f"vector.{f:04d}.exr")
    options = ["--method", "hybrid", "--mc_half_width", "2", "--float", "--quiet"]
    assert_same_output(tmp_path, options, ["--albedo", AUX / "albedo.####.exr", "--vectors", tmp_path / "vector.####.exr"],
                       [shot, "--channels", "R,G,B", "--albedo", shot, "--vectors", shot])


def test_a_layer_named_among_several_view_layers(tmp_path):
    shot = multilayer_shot(tmp_path / "shot", ("Combined", "Vector", "Other.Vector"))
    for f in FRAMES:
        vectors_file(tmp_path / f"vector.{f:04d}.exr")
    options = ["--quality", "balanced", "--float", "--quiet"]
    assert_same_output(tmp_path, options, ["--vectors", tmp_path / "vector.####.exr"],
                       [shot, "--channels", "ViewLayer.Combined", "--vectors", "Other.Vector"], "named")
    proc = run("denoise", shot, tmp_path / "o.####.exr", *options, "--channels", "ViewLayer.Combined",
               "--vectors", "ViewLayer.Motion", check_rc=1)
    assert "ViewLayer.Motion" in proc.stderr and "Other.Vector.X" in proc.stderr
    assert "taken as a layer of the input's files" in proc.stderr
    # A layer named through the albedo parameter makes a plan of the passes' format too.
    plan = tmp_path / "plan.json"
    run("plan", shot, tmp_path / "farm" / "o.####.exr", "--method", "hybrid", "--channels", "ViewLayer.Combined",
        "--albedo", "ViewLayer.Combined", "-o", plan, "--quiet")
    written = json.loads(plan.read_text())
    assert written["version"] == 2 and written["front_end"]["parameters"]["albedo"] == "ViewLayer.Combined"


@pytest.mark.parametrize("layers,pass_option,words", [
    (("Combined", "Normal"), "--albedo", ["has layers but none named for it", "ViewLayer.Normal"]),
    (("Combined", "Vector", "Other.Vector"), "--vectors", ["several layers", "ViewLayer.Vector", "Other.Vector",
                                                           "the layer's name"]),
])
def test_a_layered_pass_with_no_single_layer_for_it_is_refused(tmp_path, layers, pass_option, words):
    shot = multilayer_shot(tmp_path / "shot", layers)
    proc = run("denoise", shot, tmp_path / "o.####.exr", "--quality", "balanced", "--channels", "ViewLayer.Combined",
               pass_option, shot, "--quiet", check_rc=1)
    for word in words:
        assert word in proc.stderr
    assert not list(tmp_path.glob("o.*.exr"))
