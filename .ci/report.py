#!/usr/bin/env python3
"""Where CI's test time went, from cargo-nextest's JUnit reports (.config/nextest.toml).

report.py PHASES_FILE JUNIT[:LABEL]...

Prints the time of every phase .ci/run recorded, the slowest 15 tests, each test binary's
total against its budget (docs/CODE_STYLE.md, "What a test may cost"), and last the plain
line `tests: N passed, N failed`. Exits non-zero when a test failed; a binary over its budget
is named (a warning, so that a slow host does not fail a good change) for the next change to
take back.
"""
import sys
import xml.etree.ElementTree as ET

# Seconds of test time per binary (the sum of its tests' times, as nextest reports them on
# the project's 2-core machine), and per test.
BUDGETS = {
    "windloom": 20,
    "windloom::doc": 20,
    "windloom::export": 90,
    "windloom::sim": 850,
    "windloom::ui": 270,
}
PER_TEST = 60


def main():
    phases_file, reports = sys.argv[1], sys.argv[2:]
    print("\n== CI phases (seconds) ==")
    total = 0
    with open(phases_file) as f:
        for line in f:
            name, secs = line.rsplit(maxsplit=1)
            total += int(secs)
            print(f"{int(secs):6d}  {name}")
    print(f"{total:6d}  total so far")

    cases = []  # (seconds, run, binary, test, status)
    for spec in reports:
        path, _, label = spec.partition(":")
        try:
            root = ET.parse(path).getroot()
        except (OSError, ET.ParseError) as e:
            print(f"report.py: cannot read {path}: {e}")
            return 1
        for suite in root.iter("testsuite"):
            for case in suite.iter("testcase"):
                if case.find("skipped") is not None:
                    continue
                failed = case.find("failure") is not None or case.find("error") is not None
                cases.append(
                    (float(case.get("time", 0)), label or "vulkan", suite.get("name"),
                     case.get("name"), "FAIL" if failed else "pass")
                )

    print("\n== The slowest 15 tests (seconds) ==")
    for secs, run, binary, name, status in sorted(cases, reverse=True)[:15]:
        flag = "  over the per-test budget" if secs > PER_TEST else ""
        print(f"{secs:8.1f}  {status}  [{run}] {binary} {name}{flag}")

    print("\n== Test time per binary against its budget (seconds) ==")
    for run in dict.fromkeys(c[1] for c in cases):
        sums = {}
        for secs, r, binary, _, _ in cases:
            if r == run:
                sums[binary] = sums.get(binary, 0.0) + secs
        for binary, secs in sorted(sums.items()):
            budget = BUDGETS.get(binary)
            if run != "vulkan":
                note = ""
            elif budget is None:
                note = "  (no budget: add one to .ci/report.py)"
            elif secs > budget:
                note = f"  OVER its budget of {budget} s"
            else:
                note = f"  (budget {budget})"
            print(f"{secs:8.1f}  [{run}] {binary}{note}")

    passed = sum(1 for c in cases if c[4] == "pass")
    failed = sum(1 for c in cases if c[4] == "FAIL")
    print(f"\ntests: {passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
