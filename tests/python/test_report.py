"""python -m statfilter.report on the shipped sample: the page holds its parts, with the numbers
and pictures they should have; in headless Chromium when it is installed."""

import base64
import os
import re
import shutil
import struct
import subprocess
import sys
import zlib

import numpy as np
import pytest

import statfilter
from statfilter import report

HERE = os.path.dirname(os.path.abspath(__file__))
SAMPLE = os.path.normpath(os.path.join(HERE, "..", "..", "sample", "cornell_moving"))
NOISY = os.path.join(SAMPLE, "spp0004", "indirect.####.exr")
REF = os.path.join(SAMPLE, "ref", "indirect.####.exr")
FRAMES = "1-8"


def decode_png(data):
    """(height, width, 3) uint8 of the report's PNGs: 8-bit RGB, every row unfiltered (filter 0)."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos, idat, header = 8, b"", None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + length]
        assert zlib.crc32(kind + body) == struct.unpack(">I", data[pos + 8 + length:pos + 12 + length])[0]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    w, h, depth, colour = header[:4]
    assert depth == 8 and colour == 2, header
    rows = np.frombuffer(zlib.decompress(idat), np.uint8).reshape(h, 1 + 3 * w)
    assert np.all(rows[:, 0] == 0)
    return rows[:, 1:].reshape(h, w, 3)


def images(page):
    return [base64.b64decode(m) for m in re.findall(r'src="data:image/png;base64,([A-Za-z0-9+/=]+)"', page)]


@pytest.fixture(scope="module")
def shot(tmp_path_factory):
    """The sample's first 8 frames, denoised by pca, and the report on them with the reference."""
    d = tmp_path_factory.mktemp("report")
    noisy, info = statfilter.read_sequence(NOISY, frames=FRAMES, return_info=True)
    with statfilter.Filter("pca", rank=1) as f:
        den = f(noisy)
    statfilter.write_sequence(str(d / "den.####.exr"), den, pixel_type="float", frame_numbers=info.frame_numbers,
                              channel_names=info.channel_names)
    page = d / "report.html"
    proc = subprocess.run([sys.executable, "-m", "statfilter.report", NOISY, str(d / "den.####.exr"), "--ref", REF,
                           "--frames", FRAMES, "-o", str(page)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    return d, page.read_text(), noisy, den, statfilter.read_sequence(REF, frames=FRAMES)


def test_the_page_has_every_part(shot):
    _, page, noisy, den, ref = shot
    for section in ("summary", "choice", "frames", "maps", "errors"):
        assert '<section id="%s">' % section in page, section
    # Self-contained: nothing is fetched.
    assert not re.search(r'(src|href)="(?!data:)', page)
    # The first, the worst (against REF) and the last frame, three panels each; maps: alpha, beta of
    # each frame shown, the rank map, and auto's own alpha and motion path (all zero: a still shot).
    worst = 1 + int(np.argmax([statfilter.compare(den[i:i + 1], ref[i:i + 1])["rel_mse"] for i in range(8)]))
    shown = [int(f) for f in re.findall(r'<div class="frame" data-frame="(\d+)">', page)]
    assert shown == sorted({1, worst, 8})
    assert len(images(page)) == 3 * len(shown) + len(shown) + 4
    assert page.count('<svg class="legend"') == len(shown) + 4


def test_pictures_are_the_frames_at_one_exposure(shot):
    _, page, noisy, den, ref = shot
    first = [decode_png(p) for p in images(page)[:3]]
    for picture in first:
        assert picture.shape == (120, 160, 3)
    exposure = 1.0 / np.percentile(ref[0], 99.0)
    for picture, frame in zip(first, (noisy[0], den[0], ref[0])):
        np.testing.assert_array_equal(picture, report.tonemap(frame, exposure))
    # The noisy picture is the noisier one.
    assert np.std(first[0].astype(float) - first[2]) > 1.2 * np.std(first[1].astype(float) - first[2])


def test_the_choice_is_what_auto_reports(shot):
    _, page, noisy, _, _ = shot
    with statfilter.Filter("auto") as f:
        f(noisy)
        results = f.results
    assert '<p id="chosen-method"><b>method:</b> %s</p>' % results["method"] in page
    assert results["reason"].split(":")[0] in page


def test_errors_per_frame_are_the_librarys(shot):
    _, page, noisy, den, ref = shot
    series = dict(re.findall(r'<polyline class="series" data-name="([^"]+)"[^>]* points="([^"]+)"', page))
    assert set(series) == {"IN (noisy)", "OUT (denoised)"}
    assert all(len(p.split()) == 8 for p in series.values())
    # Captions carry the same numbers as compare(); the denoised frames are below the noisy ones.
    for i in (0, 7):
        rel = statfilter.compare(den[i:i + 1], ref[i:i + 1])["rel_mse"]
        assert "OUT (denoised), relMSE %s" % report._num(rel) in page
    total = statfilter.compare(den, ref)["rel_mse"]
    assert "<tr><th>rel_mse</th><td>%s</td><td>%s</td></tr>" % (
        report._num(statfilter.compare(noisy, ref)["rel_mse"]), report._num(total)) in page
    ys = {k: [float(p.split(",")[1]) for p in v.split()] for k, v in series.items()}
    assert max(ys["IN (noisy)"]) < min(ys["OUT (denoised)"])  # SVG y grows downward: IN is higher


def test_without_a_reference_and_bad_arguments(shot, tmp_path):
    d = shot[0]
    page = tmp_path / "r.html"
    subprocess.run([sys.executable, "-m", "statfilter.report", NOISY, str(d / "den.####.exr"), "--frames", FRAMES,
                    "--show", "3", "--no-maps", "-o", str(page)], check=True, capture_output=True)
    text = page.read_text()
    assert '<section id="errors">' not in text and '<section id="maps">' in text  # auto's alpha and motion path only
    assert re.findall(r'data-frame="(\d+)"', text) == ["3"]
    assert len(images(text)) == 2 + 2
    bad = subprocess.run([sys.executable, "-m", "statfilter.report", NOISY, str(d / "den.####.exr"), "--frames", FRAMES,
                          "--show", "40", "-o", str(tmp_path / "x.html")], capture_output=True, text=True)
    assert bad.returncode == 2 and "frame(s) 40 are not in the sequence" in bad.stderr
    assert not (tmp_path / "x.html").exists()


@pytest.mark.skipif(shutil.which("chromium") is None, reason="no headless chromium (apt-get install chromium)")
def test_chromium_renders_the_page(shot):
    d, page, _, _, _ = shot
    png_path = d / "shot.png"
    subprocess.run(["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                    "--window-size=1000,3200", "--screenshot=%s" % png_path, (d / "report.html").as_uri()],
                   check=True, capture_output=True, timeout=120,
                   env={k: v for k, v in os.environ.items() if k not in ("LD_PRELOAD", "ASAN_OPTIONS")})
    pixels = np.rint(statfilter.read_sequence(str(png_path))[0][:, :, :3] * 255).astype(int)
    assert pixels.shape[:2] == (3200, 1000)
    # The pictures and the legends were drawn: the room's pixels and viridis' yellow end are there.
    yellow = np.all(np.abs(pixels - [253, 231, 37]) <= 12, axis=2)
    assert yellow.sum() > 200
    assert (pixels.sum(axis=2) < 600).mean() > 0.05  # far from a blank white page
