"""The run report (docs/report.md) in a real browser: Debian's Chromium, headless, drawing WebGL with
SwiftShader (on a machine without a GPU, --disable-gpu would leave the canvas empty).

ctest runs this file with CLOTHSIM_EXE set to the built command (tests/report/CMakeLists.txt). The
page writes a JSON status line (#report-status) once it has drawn; "#frame=last" opens it at the last
frame and "#probe" adds the positions it draws.
"""

import json
import os
import re
import shutil
import struct
import subprocess
import tempfile
import zlib

import pytest

EXE = os.environ["CLOTHSIM_EXE"]
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
BROWSER_FLAGS = ["--headless", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
                 "--virtual-time-budget=15000", "--hide-scrollbars", "--no-first-run", "--disable-extensions",
                 # Nothing but the file itself: a page that fetched anything would fail to load it.
                 "--host-resolver-rules=MAP * ~NOTFOUND"]
WINDOW = (1280, 2300)
BROWSER_FLAGS.append(f"--window-size={WINDOW[0]},{WINDOW[1]}")  # the status's rectangles are the screenshot's


def chromium(*args, cwd):
    assert CHROMIUM, "Chromium is not installed (scripts/install-deps.sh installs Debian's chromium)"
    # A profile of its own: two browsers on one profile would hand the page to the first one.
    with tempfile.TemporaryDirectory(prefix="chromium-profile-") as profile:
        return subprocess.run([CHROMIUM, *BROWSER_FLAGS, f"--user-data-dir={profile}", *args], cwd=cwd,
                              capture_output=True, text=True, timeout=180)


def page_status(report, fragment):
    process = chromium("--dump-dom", f"file://{report}#{fragment}", cwd=report.parent)
    found = re.search(r'<pre id="report-status"[^>]*>(.*?)</pre>', process.stdout, re.S)
    assert found, f"the page wrote no status: {process.stderr[-2000:]}"
    return json.loads(found.group(1).replace("&quot;", '"').replace("&amp;", "&"))


def read_png(path):
    """The pixels of an 8-bit RGB or RGBA PNG, as rows of bytes, and its channel count."""
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    at, chunks, header = 8, [], None
    while at < len(data):
        length, kind = struct.unpack(">I4s", data[at:at + 8])
        body = data[at + 8:at + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            chunks.append(body)
        at += 12 + length
    width, height, depth, colour, _, _, interlace = header
    assert depth == 8 and colour in (2, 6) and interlace == 0, header
    channels = 3 if colour == 2 else 4
    raw = zlib.decompress(b"".join(chunks))
    stride = width * channels
    rows, previous = [], bytearray(stride)
    for y in range(height):
        kind, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            left = line[x - channels] if x >= channels else 0
            up = previous[x]
            corner = previous[x - channels] if x >= channels else 0
            if kind == 1:
                line[x] = (line[x] + left) & 255
            elif kind == 2:
                line[x] = (line[x] + up) & 255
            elif kind == 3:
                line[x] = (line[x] + (left + up) // 2) & 255
            elif kind == 4:
                p = left + up - corner
                pa, pb, pc = abs(p - left), abs(p - up), abs(p - corner)
                line[x] = (line[x] + (left if pa <= pb and pa <= pc else up if pb <= pc else corner)) & 255
        rows.append(bytes(line))
        previous = line
    return rows, channels


def colours_in(rows, channels, rect):
    """The distinct colours inside rect = [left, top, width, height]."""
    left, top, width, height = rect
    seen = set()
    for y in range(top + 2, top + height - 2, 2):
        row = rows[y]
        for x in range(left + 2, left + width - 2, 2):
            seen.add(row[x * channels:x * channels + 3])
    return seen


def final_obj_vertices(folder):
    return [tuple(float(v) for v in line.split()[1:4])
            for line in (folder / "final.obj").read_text().splitlines() if line.startswith("v ")]


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """Three runs with their reports: a sheet that tears in two, one whose anchors let go, one on obstacles."""
    root = tmp_path_factory.mktemp("report")
    made = {}
    for name, args in {
        "tear-pull": ["--duration", "0.8", "--export", "gltf-animation"],
        "paper-crease": ["--duration", "1.0"],
        "drape-sphere": ["--duration", "0.5"],
    }.items():
        folder = root / name
        process = subprocess.run([EXE, "run", name, *args, "--render", "none", "--report", "--out", str(folder),
                                  "--quiet"], capture_output=True, text=True, timeout=600)
        assert process.returncode == 0, process.stderr
        made[name] = folder
    return made


@pytest.mark.parametrize("name", ["tear-pull", "paper-crease", "drape-sphere"])
def test_the_page_loads_with_every_frame_and_draws_the_last_one_as_final_obj(runs, name):
    folder = runs[name]
    summary = json.loads((folder / "summary.json").read_text())
    status = page_status(folder / "report.html", "frame=last&probe")
    assert status["ready"] and status["errors"] == []
    assert status["frames"] == summary["frames"] == status["total_frames"]
    assert status["frame"] == summary["frames"] - 1
    # The last frame drawn is final.obj: the same mesh (split along tears), at the same positions
    # within float32 rounding.
    expected = final_obj_vertices(folder)
    drawn = status["positions"]
    assert status["vertices"] == len(expected) == len(drawn) // 3
    worst = max(abs(drawn[3 * i + k] - v[k]) / max(1.0, abs(v[k])) for i, v in enumerate(expected) for k in range(3))
    assert worst < 1e-6


def test_a_torn_sheet_is_drawn_in_two_pieces_and_whole_before_it_tears(runs):
    report = runs["tear-pull"] / "report.html"
    first = page_status(report, "frame=0")
    last = page_status(report, "frame=last")
    # One piece at the start, split vertices only along the notch cut before the run; two pieces
    # at the end, split along the tear as well (the cells across it drawn as quarter cells).
    assert first["pieces"] == 1 and 21 * 21 < first["vertices"] < last["vertices"]
    assert last["pieces"] == 2
    assert last["anchors_shown"] == first["anchors_shown"] == 42  # rows 0 and 20 stay held


def test_released_anchors_are_not_drawn_after_they_let_go(runs):
    report = runs["paper-crease"] / "report.html"
    scene = json.loads((runs["paper-crease"] / "scene.json").read_text())
    anchors = scene["anchors"]
    released = [a for a in anchors if a.get("release_time") is not None and a["release_time"] <= 1.0]
    assert released, "paper-crease lets some anchors go before 1 s"
    assert page_status(report, "frame=0")["anchors_shown"] == len(anchors)
    assert page_status(report, "frame=last")["anchors_shown"] == len(anchors) - len(released)


def test_the_view_and_every_plot_are_drawn(runs, tmp_path):
    for name in ("drape-sphere", "tear-pull"):
        report = runs[name] / "report.html"
        status = page_status(report, "frame=last")
        shot = tmp_path / f"{name}.png"
        process = chromium(f"--screenshot={shot}", f"file://{report}#frame=last", cwd=tmp_path)
        assert shot.exists(), process.stderr[-2000:]
        rows, channels = read_png(shot)
        assert len(rows) == WINDOW[1]
        # The 3D view: the sheet shaded (many colours), not the background alone.
        view = status["view"]
        assert view[1] + view[3] <= WINDOW[1]
        assert len(colours_in(rows, channels, view)) > 50, name
        # Each plot: its frame, lines and labels, not an empty box.
        assert len(status["plots"]) == 7
        for rect in status["plots"]:
            assert rect[1] + rect[3] <= WINDOW[1], "the screenshot is too short for the plots"
            assert len(colours_in(rows, channels, rect)) > 4, (name, rect)


def test_clothsim_report_writes_the_page_of_a_folder_and_refuses_what_is_not_a_run(runs, tmp_path):
    folder = runs["drape-sphere"]
    (folder / "report.html").unlink()
    process = subprocess.run([EXE, "report", str(folder)], capture_output=True, text=True, timeout=300)
    assert process.returncode == 0, process.stderr
    assert (folder / "report.html").exists()
    empty = tmp_path / "empty"
    empty.mkdir()
    process = subprocess.run([EXE, "report", str(empty)], capture_output=True, text=True, timeout=60)
    assert process.returncode == 2 and "scene.json" in process.stderr and "is missing" in process.stderr
    assert not (empty / "report.html").exists()


def test_animation_glb_plays_in_a_browser_with_three_js(runs, tmp_path):
    """--export gltf-animation's file in a browser viewer: three.js's GLTFLoader and AnimationMixer,
    in headless Chromium, play it as the run ran: at each frame time the particles are positions.npy's
    frame, halfway between two frames their mean, and at the end every vertex is final.obj's."""
    import numpy
    folder = runs["tear-pull"]
    summary = json.loads((folder / "summary.json").read_text())
    fps = summary["fps"]
    frames = numpy.load(folder / "positions.npy")
    last = len(frames) - 1
    times = [0.0, 20 / fps, 20.5 / fps, last / fps]
    viewer = os.path.join(os.path.dirname(os.path.abspath(__file__)), "animation_viewer.html")
    address = f"file://{viewer}#glb=file://{folder / 'animation.glb'}&times={','.join(map(repr, times))}"
    process = chromium("--allow-file-access-from-files", "--dump-dom", address, cwd=tmp_path)
    found = re.search(r'<pre id="viewer-status"[^>]*>(.*?)</pre>', process.stdout, re.S)
    assert found, process.stderr[-2000:]
    status = json.loads(found.group(1).replace("&quot;", '"').replace("&amp;", "&"))
    assert status["ready"] and status["errors"] == [], status.get("load_error")
    assert status["targets"] == len(frames) and abs(status["duration"] - last / fps) < 1e-6
    particles = frames.shape[1]
    expected = [frames[0], frames[20], 0.5 * (frames[20] + frames[21]), frames[last]]
    for sample, want in zip(status["samples"], expected):
        assert abs(sample["weight_sum"] - 1.0) < 1e-6
        drawn = numpy.array(sample["positions"]).reshape(-1, 3)
        assert numpy.abs(drawn[:particles] - want).max() < 1e-6 * max(1.0, numpy.abs(want).max())
    # The end: the whole mesh, split along the tear, is final.obj.
    drawn = numpy.array(status["samples"][-1]["positions"]).reshape(-1, 3)
    assert numpy.abs(drawn - numpy.array(final_obj_vertices(folder))).max() < 1e-6
