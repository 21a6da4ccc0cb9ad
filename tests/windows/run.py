#!/usr/bin/env python3
"""windloom's Windows build run for real: the binary cross-linked with Debian's mingw-w64
(x86_64-pc-windows-gnu), run under Wine, and held to the Linux build of the same code.

    python3 tests/windows/run.py --exe target/x86_64-pc-windows-gnu/ci/windloom.exe \\
        --linux target/ci/windloom

On every example layout (layouts/): `validate` and `fmt` give the same output and files;
`bake` (every format, a 3-frame looping sequence) writes byte-identical files, manifest
included, into a new folder (and, for the meadow, again into that folder with a file of the
user's in it, which stays);
`render` writes a byte-identical PNG; `probe` prints the same figures. `schema` prints the
same schemas. A layout saved on Windows (CRLF, image paths written with `\\`) bakes as the
Linux layout does. The refusals are those of Linux: a name Windows cannot hold (`CON`), a
missing layout, a bad flag (same exit status, one line naming the field or file). And the
folder discipline Windows makes hard: a bake over a folder with one of its files held open
by another program (tests/windows/hold.c, opening it as an engine's importer does) is
refused naming that file, leaves the previous bake byte for byte, and `bake --watch` keeps
watching and bakes once the file is let go.

What Wine cannot stand for is in docs/RELIABILITY.md ("Windows").

Exit status 0 when every check holds; 1 with one line per failure otherwise; 2 when Wine
or mingw-w64 is missing (CI sets WINDLOOM_REQUIRE_WINE=1 and then fails instead).
"""

import argparse
import filecmp
import hashlib
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
HERE = Path(__file__).resolve().parent
EXAMPLES = ["meadow", "branching", "breeze-fft", "obstacles", "two-winds", "walled-garden"]
AGAIN = ["meadow"]
MINGW = "x86_64-w64-mingw32-gcc"

failures = []


def fail(message):
    failures.append(message)
    print("FAIL " + message, flush=True)


def missing(what):
    message = f"windows run: {what}"
    if os.environ.get("WINDLOOM_REQUIRE_WINE") == "1":
        print(f"error: {message} (WINDLOOM_REQUIRE_WINE=1)", file=sys.stderr)
        sys.exit(1)
    print(f"SKIPPED (loudly): {message}", file=sys.stderr)
    sys.exit(2)


class Runner:
    """Runs windloom on Linux and on Windows (under Wine) in one work folder."""

    def __init__(self, linux, exe, work, env):
        self.linux, self.exe, self.work, self.env = linux, exe, work, env

    def start(self, windows, *args):
        cmd = (["wine", str(self.exe)] if windows else [str(self.linux)]) + list(args)
        return subprocess.Popen(
            cmd, cwd=self.work, env=self.env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
        )

    def run(self, windows, *args, timeout=600):
        return finish(self.start(windows, *args), timeout)

    def pair(self, lin_args, win_args, timeout=600):
        """A command on Linux and one on Windows, side by side (the machine's two cores);
        the Windows output with CRLF read as LF."""
        lin, win = self.start(False, *lin_args), self.start(True, *win_args)
        lin, win = finish(lin, timeout), finish(win, timeout)
        win.stdout = win.stdout.replace("\r\n", "\n")
        win.stderr = win.stderr.replace("\r\n", "\n")
        return lin, win

    def both(self, *args):
        """The same command on both."""
        return self.pair(args, args)


def finish(p, timeout):
    try:
        out, err = p.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        p.kill()
        out, err = p.communicate()
        err += f"\n(killed after {timeout} s)"
    return subprocess.CompletedProcess(p.args, p.returncode, out, err)


def digest(folder):
    """Every file under `folder`: relative name -> sha256. windloom's own lock files
    (`.windloom-bake-*`: on Windows, the folder's commit lock) are no one's output."""
    out = {}
    for p in sorted(Path(folder).rglob("*")):
        if p.is_file() and not p.name.startswith(".windloom-bake-"):
            out[p.relative_to(folder).as_posix()] = hashlib.sha256(p.read_bytes()).hexdigest()
    return out


def same_folders(what, lin, win, skip=()):
    a, b = digest(lin), digest(win)
    for name in sorted(set(a) | set(b)):
        if name in skip:
            continue
        if name not in a or name not in b:
            fail(f"{what}: {name} written on {'Windows' if name in b else 'Linux'} only")
        elif a[name] != b[name]:
            fail(f"{what}: {name} differs between the Linux and Windows bakes")


def same_output(what, lin, win):
    if lin.returncode != win.returncode:
        fail(f"{what}: exit {lin.returncode} on Linux, {win.returncode} on Windows: {win.stderr.strip()}")
    if lin.stdout != win.stdout:
        fail(f"{what}: stdout differs:\n--- Linux\n{lin.stdout}--- Windows\n{win.stdout}")


def one_line_refusal(what, lin, win, names):
    """Both refuse, with the same status, in one line (stderr's `error:` line, or
    validate's report on stdout) that names `names`."""
    if lin.returncode == 0 or win.returncode != lin.returncode:
        fail(f"{what}: exit {lin.returncode} on Linux, {win.returncode} on Windows")
    for side, r in (("Linux", lin), ("Windows", win)):
        said = (r.stdout + r.stderr).strip().splitlines()
        lines = [l for l in said if not l.startswith("warning:")]
        if len(lines) != 1 or names not in lines[0]:
            fail(f"{what}: {side} did not refuse in one line naming {names!r}: {(r.stdout + r.stderr).strip()!r}")


def stand_ins(prefix, bindir):
    """Debian 12's Wine 8 has no bcryptprimitives.dll, whose ProcessPrng Rust's standard
    library calls for random numbers (Windows 10 and later have it): a stand-in calling
    RtlGenRandom goes beside the binary where Wine lacks it. And hold.exe."""
    system = prefix / "drive_c" / "windows" / "system32"
    if not (system / "bcryptprimitives.dll").exists():
        subprocess.run(
            [MINGW, "-shared", "-O2", "-o", str(bindir / "bcryptprimitives.dll"),
             str(HERE / "bcryptprimitives.c"), "-ladvapi32"],
            check=True,
        )
    subprocess.run([MINGW, "-O2", "-o", str(bindir / "hold.exe"), str(HERE / "hold.c")], check=True)


def check_examples(r):
    for name in EXAMPLES:
        layout = f"layouts/{name}.json"
        t = time.monotonic()
        same_output(f"validate {name}", *r.both("validate", layout))
        lin, win = r.both("probe", layout, "--warmup", "0.5", "--seconds", "0.5", "--hz", "10")
        same_output(f"probe {name}", lin, win)
        picture = ["--size", "400x250", "--time", "0.5"]
        lin, win = r.pair(["render", layout, "-o", f"lin-{name}.png", *picture],
                          ["render", layout, "-o", f"win-{name}.png", *picture])
        if lin.returncode or win.returncode:
            fail(f"render {name}: exit {lin.returncode} / {win.returncode}: {win.stderr.strip()}")
        elif not filecmp.cmp(r.work / f"lin-{name}.png", r.work / f"win-{name}.png", shallow=False):
            fail(f"render {name}: the PNGs differ")
        bake = ["--frames", "3", "--loop", "--fps", "10", "--warmup", "1"]
        # Into a new folder for every example; again into it, with the user's file there,
        # for one (a terrain bake's re-bake: tests/export/terrain.rs).
        for rep in (1, 2) if name in AGAIN else (1,):
            lin, win = r.pair(["bake", layout, "--out", f"lin/{name}", *bake],
                              ["bake", layout, "--out", f"win/{name}", *bake])
            if lin.returncode or win.returncode:
                fail(f"bake {name} ({rep}): exit {lin.returncode} / {win.returncode}: {win.stderr.strip()}")
                continue
            same_folders(f"bake {name} ({'new' if rep == 1 else 'existing'} folder)",
                         r.work / "lin" / name, r.work / "win" / name)
            if rep == 1:
                # The user's own file, which the re-bake must keep.
                for side in ("lin", "win"):
                    (r.work / side / name / "notes.txt").write_text("mine\n")
        if (r.work / "win" / name / "notes.txt").read_text() != "mine\n":
            fail(f"bake {name}: the user's notes.txt was not kept on Windows")
        bakes = "bake twice" if name in AGAIN else "bake"
        print(f"ok   {name}: validate, probe, render, {bakes} ({time.monotonic() - t:.0f} s)", flush=True)

    # fmt: the same files out of the same files.
    for side in ("lin", "win"):
        shutil.copytree(ROOT / "layouts", r.work / f"fmt-{side}")
    files = [f"fmt-{{}}/{n}.json" for n in EXAMPLES]
    lin, win = r.pair(["fmt", *[f.format("lin") for f in files]], ["fmt", *[f.format("win") for f in files]])
    if lin.returncode or win.returncode:
        fail(f"fmt: exit {lin.returncode} / {win.returncode}: {win.stderr.strip()}")
    same_folders("fmt", r.work / "fmt-lin", r.work / "fmt-win")
    for args in (["schema"], ["schema", "--manifest"]):
        same_output(" ".join(args), *r.both(*args))
    print("ok   fmt, schema", flush=True)


def check_portable(r):
    """A layout as Windows saves it by hand (CRLF, image paths with backslashes) and the same
    layout as Linux saves it: the same bake, manifest and all, on either system."""
    folder = r.work / "portable"
    (folder / "images").mkdir(parents=True)
    text = (ROOT / "layouts" / "walled-garden.json").read_text()
    for image in ("walled-garden-mask.png", "walled-garden-heights.png", "walled-garden-grass.png"):
        shutil.copy(ROOT / "layouts" / image, folder / "images" / image)
        text = text.replace(f'"{image}"', f'"images/{image}"')
    if text.count('"images/') < 2:
        fail("portable: the walled garden names fewer images than expected")
    (folder / "linux.json").write_text(text)
    (folder / "windows.json").write_bytes(text.replace("images/", "images\\\\").replace("\n", "\r\n").encode())
    bake = ["--frames", "1", "--warmup", "1"]
    lin = r.run(False, "bake", "portable/linux.json", "--out", "portable/lin-lin", *bake)
    if lin.returncode:
        fail(f"portable: the Linux bake failed: {lin.stderr.strip()}")
        return
    for windows, layout in ((True, "linux"), (True, "windows"), (False, "windows")):
        side = "Windows" if windows else "Linux"
        out = f"portable/{side}-{layout}"
        got = r.run(windows, "bake", f"portable/{layout}.json", "--out", out, *bake)
        if got.returncode:
            fail(f"portable ({side} reading {layout}.json): exit {got.returncode}: {got.stderr.strip()}")
            continue
        same_folders(f"portable ({side} reading {layout}.json)", folder / "lin-lin", r.work / out)
    print("ok   layouts saved on either system (CRLF, backslashes) bake the same on both", flush=True)


def check_refusals(r):
    # A layout naming a file Windows keeps for a device: refused at bake, on Windows before
    # it opens the console.
    text = (ROOT / "layouts" / "walled-garden.json").read_text()
    (r.work / "layouts" / "reserved.json").write_text(text.replace("walled-garden-mask.png", "CON.png"))
    lin, win = r.both("bake", "layouts/reserved.json", "--out", "reserved-bake")
    one_line_refusal("a layout naming CON.png", lin, win, "CON.png")
    if (r.work / "reserved-bake").exists():
        fail("a refused bake left a folder behind")
    lin, win = r.both("validate", "layouts/no-such.json")
    one_line_refusal("a missing layout", lin, win, "no-such.json")
    lin, win = r.both("bake", "layouts/meadow.json", "--out", "x", "--grid", "32")
    if lin.returncode == 0 or lin.returncode != win.returncode or "--grid" not in win.stderr:
        fail(f"a bad --grid: exit {lin.returncode} / {win.returncode}: {win.stderr.strip()!r}")
    print("ok   refusals as on Linux", flush=True)


def check_held(r, env, bindir):
    """An engine holds a file of the old bake open: the bake says which, and leaves the
    old bake whole; --watch keeps watching and bakes once the file is let go."""

    def hold(path):
        h = subprocess.Popen(
            ["wine", str(bindir / "hold.exe"), path, "600"],
            cwd=r.work, env=env, stdout=subprocess.PIPE, text=True,
        )
        if h.stdout.readline().strip() != "held":
            fail(f"held: hold.exe did not open {path}")
        return h

    def let_go(h):
        h.kill()
        h.wait()
        # Wine closes the dead process's handles in its server, a moment later.
        time.sleep(1)

    out = r.work / "win" / "meadow"
    files = [f["name"] for f in json.loads((out / "manifest.json").read_text())["files"]]
    before = digest(out)
    h = hold(f"win/meadow/{files[0]}")
    got = r.run(True, "bake", "layouts/meadow.json", "--out", "win/meadow", "--frames", "1", "--warmup", "1")
    let_go(h)
    line = got.stderr.strip()
    if got.returncode == 0 or files[0] not in line or "open in another program" not in line:
        fail(f"held: the bake did not refuse naming {files[0]}: exit {got.returncode}: {line!r}")
    if digest(out) != before:
        fail("held: the previous bake changed")
    leftovers = [p.name for p in (r.work / "win").iterdir() if p.name.startswith(".windloom-bake-")]
    if leftovers:
        fail(f"held: the refused bake left {leftovers}")
    print("ok   a file held open: refused naming it, the previous bake kept", flush=True)

    # --watch through it: a save while a file is held is reported, the bake kept; the next
    # save after the file is let go bakes.
    layout = r.work / "layouts" / "watched.json"
    shutil.copy(ROOT / "layouts" / "meadow.json", layout)
    args = ["bake", "layouts/watched.json", "--out", "win/meadow", "--frames", "1", "--warmup", "1", "--watch"]
    log_path = r.work / "watch.log"
    log = open(log_path, "w")
    watch = subprocess.Popen(["wine", str(r.exe), *args], cwd=r.work, env=env, stdout=log, stderr=subprocess.STDOUT)

    def wait_for(text, seconds=120):
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            if text in log_path.read_text(errors="replace"):
                return True
            if watch.poll() is not None:
                return False
            time.sleep(0.5)
        return False

    def save():
        layout.write_text(layout.read_text() + "\n")

    h = None
    try:
        if not wait_for("watching", 180):
            fail(f"watch: the first bake did not finish: {log_path.read_text()!r}")
            return
        files = [f["name"] for f in json.loads((out / "manifest.json").read_text())["files"]]
        h = hold(f"win/meadow/{files[-1]}")
        held = digest(out)
        save()
        if not wait_for("open in another program"):
            fail("watch: a save while a file is held was not reported")
        if digest(out) != held:
            fail("watch: the bake changed while a file of it was held")
        let_go(h)
        save()
        if not wait_for("sequence 4"):
            fail(f"watch: no bake after the file was let go: {log_path.read_text()!r}")
        if watch.poll() is not None:
            fail("watch: it stopped")
    finally:
        watch.kill()
        if h:
            h.kill()
        log.close()
    print("ok   --watch keeps going past a held file", flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--exe", required=True, type=Path, help="the Windows windloom.exe")
    parser.add_argument("--linux", required=True, type=Path, help="the Linux windloom of the same code")
    parser.add_argument("--keep", type=Path, help="keep the work folder here")
    args = parser.parse_args()
    for tool in ("wine", "wineboot", MINGW):
        if shutil.which(tool) is None:
            missing(f"{tool} is not installed (apt: wine wine64 gcc-mingw-w64-x86-64)")
    for p in (args.exe, args.linux):
        if not p.is_file():
            print(f"error: {p}: no such file (build it first)", file=sys.stderr)
            sys.exit(1)

    tmp = Path(tempfile.mkdtemp(prefix="windloom-windows-"))
    work, prefix, bindir = tmp / "work", tmp / "prefix", tmp / "bin"
    work.mkdir()
    bindir.mkdir()
    shutil.copytree(ROOT / "layouts", work / "layouts")
    env = dict(os.environ, WINEPREFIX=str(prefix), WINEDEBUG="-all", WINEDLLOVERRIDES="mscoree,mshtml=")
    t = time.monotonic()
    subprocess.run(["wineboot", "-i"], env=env, check=True, capture_output=True)
    print(f"ok   a fresh Wine prefix ({time.monotonic() - t:.0f} s)", flush=True)
    exe = bindir / "windloom.exe"
    shutil.copy(args.exe, exe)
    stand_ins(prefix, bindir)
    r = Runner(args.linux.resolve(), exe, work, env)
    try:
        check_examples(r)
        check_portable(r)
        check_refusals(r)
        check_held(r, env, bindir)
    finally:
        subprocess.run(["wineserver", "-k"], env=env, capture_output=True)
        if args.keep:
            shutil.rmtree(args.keep, ignore_errors=True)
            shutil.copytree(work, args.keep)
        shutil.rmtree(tmp, ignore_errors=True)
    if failures:
        print(f"{len(failures)} Windows check(s) failed", file=sys.stderr)
        sys.exit(1)
    print("windows run: every check holds")


if __name__ == "__main__":
    main()
