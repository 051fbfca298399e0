#!/usr/bin/env python3
"""A long session of soft translations under a change criterion (L1 or Fewest commit their
exact choice, not a snapped point): the time of every edit and the size of the committed
values, to see whether they grow. Through the Python package.

    pip install ./crates/python
    python3 tools/make_editor_bench.py /tmp/eb
    python3 tools/criteria_session.py /tmp/eb/figure.ron figure L1 4 40
"""

import random
import statistics
import sys
import time

import ecles


def bits(value):
    """The larger of numerator and denominator bit lengths of a value (Fraction or tuple)."""
    parts = value if isinstance(value, tuple) else (value,)
    return max(max(abs(p.numerator).bit_length(), p.denominator.bit_length()) for p in parts)


def main():
    run, source, criterion, reach, count = sys.argv[1:6]
    reach, count = int(reach), int(count)
    system = ecles.System.from_run_file(run)
    vertices = [n.split(".", 1)[1] for n in system.parameters
                if n.startswith(f"{source}.v") and n.split(".", 1)[1][1:].isdigit()]
    rng = random.Random(7)
    times, refused = [], 0
    for k in range(count):
        anchor = rng.choice(vertices)
        move = (f"{rng.randint(-20, 20)}/10", f"{rng.randint(-20, 20)}/10")
        operation = (f'(anchors: ["{anchor}"], neighborhood: {reach}, '
                     f'translate: ("{move[0]}", "{move[1]}"))')
        start = time.perf_counter()
        try:
            system.operate(source, operation, criterion)
        except ecles.Unsolvable:
            refused += 1
        times.append(time.perf_counter() - start)
        if (k + 1) % 10 == 0:
            largest = max(bits(v) for v in system.values.values())
            print(f"after {k + 1} edits: largest value {largest} bits", flush=True)
    first, last = times[:10], times[-10:]
    print(f"{criterion} δ {reach}, {count} edits ({refused} refused): median first 10 "
          f"{statistics.median(first) * 1e3:.0f} ms, last 10 {statistics.median(last) * 1e3:.0f} ms; "
          f"satisfied {system.analyze().to_dict()['satisfied']}")


if __name__ == "__main__":
    main()
