#!/usr/bin/env python3
"""Prints 'N passed, N failed, N skipped' from a CTest JUnit file; exits 1 on any failure."""
import sys
import xml.etree.ElementTree as ET


def main(path):
    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError) as e:
        print(f"0 passed, 1 failed, 0 skipped  (no test results: {e})")
        return 1
    passed = failed = skipped = 0
    failures = []
    for case in root.iter("testcase"):
        status = case.get("status", "run")
        if case.find("skipped") is not None or status in ("disabled", "skipped"):
            skipped += 1
        elif case.find("failure") is not None or case.find("error") is not None or status in ("fail", "notrun"):
            failed += 1
            failures.append(case.get("name"))
        else:
            passed += 1
    for name in failures:
        print(f"FAILED: {name}")
    print(f"{passed} passed, {failed} failed, {skipped} skipped")
    return 1 if failed or passed + skipped == 0 else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "ctest.xml"))
