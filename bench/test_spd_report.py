#!/usr/bin/env python3
"""test_spd_report.py — unit tests of bench/spd_report.py (stdlib unittest):
the median's confidence interval (its coverage, exactly, for 6 to 80
rounds, and wider for many scenes at once), the verdict it gives hetero
against homo, the report on a small synthetic raw.csv whose homo and
hetero have more rounds than the other renderers (spd.sh --pairs: those
rounds go into the round-by-round table only, never against another
renderer's rounds), and spd.sh refusing --pairs without --append.
Run: python3 bench/test_spd_report.py
"""
import math
import os
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import spd_report  # noqa: E402

HEADER = "scene,renderer,run,frame_s,trace_s,rays,cl_open,culled,own_s,tiles_s\n"
OTHERS = ["serial", "hetero-always", "homo-tview", "tachyon"]


def below(n, k):
    """P(Binomial(n, 1/2) < k)."""
    return sum(math.comb(n, i) for i in range(k)) / 2 ** n


class MedianIntervalTest(unittest.TestCase):
    def test_too_few_rounds_have_none(self):
        for n in range(6):
            self.assertIsNone(spd_report.median_interval(list(range(n))))

    def test_fourteen_rounds_give_the_third_and_twelfth(self):
        # the textbook ranks for n = 14 at 95 %: (3, 12), 98.7 % coverage
        values = [float(v) for v in range(1, 15)]
        self.assertEqual(spd_report.median_interval(values), (3.0, 12.0))

    def test_many_scenes_widen_the_interval(self):
        # 30 rounds: ranks (10, 21) at 95 %, (7, 24) at 1 - 0.05 / 26
        values = [float(v) for v in range(1, 31)]
        self.assertEqual(spd_report.median_interval(values), (10.0, 21.0))
        self.assertEqual(spd_report.median_interval(values, 1 - 0.05 / 26), (7.0, 24.0))
        # hetero faster in 8 of 30 rounds: slower for one scene, not for 26
        ratios = sorted([0.99] * 8 + [1.02] * 22)
        self.assertEqual(spd_report.verdict(spd_report.median_interval(ratios)), "slower")
        self.assertEqual(spd_report.verdict(spd_report.median_interval(ratios, 1 - 0.05 / 26)),
                         "tie")

    def test_coverage_is_95_percent_and_no_wider_than_needed(self):
        for n in range(6, 81):
            values = list(range(n))
            lo, hi = spd_report.median_interval(values)
            k = lo + 1  # the rank of the low end (1-based)
            self.assertEqual(hi, n - k, n)  # symmetric
            self.assertGreaterEqual(1 - 2 * below(n, k), 0.95, n)
            if k + 1 <= n // 2:  # one rank narrower would miss 95 %
                self.assertLess(1 - 2 * below(n, k + 1), 0.95, n)


class VerdictTest(unittest.TestCase):
    def test_sides_of_one(self):
        self.assertEqual(spd_report.verdict((1.01, 1.2)), "slower")
        self.assertEqual(spd_report.verdict((0.8, 0.99)), "faster")
        self.assertEqual(spd_report.verdict((0.9, 1.1)), "tie")
        self.assertEqual(spd_report.verdict((1.0, 1.1)), "tie")
        self.assertEqual(spd_report.verdict(None), "—")


class ReportTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.d = self.dir.name

    def tearDown(self):
        self.dir.cleanup()

    def write_raw(self, full_rounds, pair_rounds):
        """Scene `slow`: hetero 10 % over homo in every round; scene `even`:
        hetero 5 % over, then under, in turn."""
        rows = []
        for r in range(1, full_rounds + pair_rounds + 1):
            for scene in ("slow", "even"):
                homo = 0.1 + 0.001 * (r % 7)  # some noise, the same for both
                if r > full_rounds:
                    homo *= 2  # a slower machine: never set against POV-Ray's rounds
                factor = 1.1 if scene == "slow" else (1.05 if r % 2 else 0.95)
                rows.append(f"{scene},homo,{r},{homo:.6f},{homo / 2:.6f},1000,none,0,0,0.2")
                rows.append(f"{scene},hetero,{r},{homo * factor:.6f},{homo / 2:.6f},1000,never,0,"
                            "0.0002,0.2")
                if r <= full_rounds:
                    rows += [f"{scene},{o},{r},0.2,0.15,1000,,,," for o in OTHERS]
                    rows.append(f"{scene},povray,{r},0.3,0.2,1000,,,,")
        raw = os.path.join(self.d, "raw.csv")
        with open(raw, "w") as f:
            f.write(HEADER + "\n".join(rows) + "\n")
        identical = os.path.join(self.d, "identical.txt")
        with open(identical, "w") as f:
            f.write("slow identical\neven identical\n")
        out = os.path.join(self.d, "SPD.md")
        spd_report.report(raw, identical, out)
        with open(out) as f:
            return f.read()

    def row(self, text, scene, table=1):
        """A scene's cells in the main table (0) or hetero's (1)."""
        lines = [line for line in text.splitlines() if line.startswith(f"| {scene} |")]
        self.assertEqual(len(lines), 2, text)
        return [c.strip() for c in lines[table].strip("|").split("|")]

    def test_pairs_rounds_only_in_the_round_by_round_table(self):
        text = self.write_raw(7, 13)
        self.assertIn("medians of 7 interleaved rounds,", text)
        self.assertIn("Of 20 rounds: the table's 7 and 13 of homo and hetero alone", text)
        main = self.row(text, "even", 0)
        # POV-Ray trace 0.2 / homo trace (median of the 7 full rounds: 0.103 / 2)
        self.assertEqual(main[10], f"{0.2 / (0.103 / 2):.2f}")
        self.assertEqual(main[4], "0/7")  # opened, in the full rounds
        slow = self.row(text, "slow")
        self.assertEqual(slow[3], "1.10")          # ratio of the medians
        self.assertTrue(slow[4].startswith("1.100"), slow)
        self.assertEqual(slow[6], "slower")
        self.assertEqual(slow[7], "slower")  # (all scenes: at 97.5 % each)
        self.assertEqual(slow[8], "0/20")
        even = self.row(text, "even")
        self.assertEqual(even[6], "tie")
        self.assertEqual(even[7], "tie")
        self.assertEqual(even[8], "10/20")

    def test_one_count_without_pairs(self):
        text = self.write_raw(8, 0)
        self.assertIn("medians of 8 interleaved rounds,", text)
        self.assertIn("round by round.\nThe two", text)
        self.assertEqual(self.row(text, "slow")[8], "0/8")


class SpdShTest(unittest.TestCase):
    def test_pairs_needs_append(self):
        script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "spd.sh")
        p = subprocess.run(["bash", script, "--pairs"], capture_output=True, text=True)
        self.assertEqual(p.returncode, 2)
        self.assertIn("use it with --append", p.stderr)


if __name__ == "__main__":
    unittest.main()
