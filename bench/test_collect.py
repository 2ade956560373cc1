#!/usr/bin/env python3
"""test_collect.py — unit tests of bench/collect.py (stdlib unittest):
flattening, the CSV union header, the medians and the advantage, the paired
advantage of interleaved rounds with its spread, idiff parsing, the report on
a tiny synthetic data set, and bench/run.sh refusing an --only list that is
not plain experiment names (it used to reach Python source).
Run: python3 bench/test_collect.py
"""
import csv
import io
import json
import os
import subprocess
import sys
import tempfile
import unittest
from contextlib import redirect_stdout

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import collect  # noqa: E402


def stats(mode, wall, compile_s=0.0, primary=0.0, secondary=None, sent=4, total=4):
    return {"mode": mode, "width": 64, "height": 64, "tile": 32, "ranks": 3,
            "wall_s": wall, "setup_s": 0.0, "compile_s": compile_s, "primary_s": primary,
            "secondary_s": wall - compile_s - primary if secondary is None else secondary,
            "write_s": 0.0, "tiles_total": total, "tiles_sent": sent, "tiles_degenerate": 0,
            "occupancy": 0.5, "bytes_sent": 100, "bytes_received": 200,
            "rays": {"primary": 10, "shadow": 5, "reflected": 1, "refracted": 0, "total": 16},
            "workers": [{"rank": 1, "busy_s": 0.1}, {"rank": 2, "busy_s": 0.2}]}


class CollectTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.d = self.dir.name

    def tearDown(self):
        self.dir.cleanup()

    def append(self, csv_name, st, **meta):
        js = os.path.join(self.d, "s.json")
        with open(js, "w") as f:
            json.dump(st, f)
        collect.cmd_append([os.path.join(self.d, csv_name), js] +
                           [f"{k}={v}" for k, v in meta.items()])

    def test_flatten_nested(self):
        out = {}
        collect.flatten("", {"a": 1, "rays": {"primary": 2}, "w": [{"x": 3}]}, out)
        self.assertEqual(out, {"a": 1, "rays_primary": 2, "w_0_x": 3})

    def test_time_excludes_compile(self):
        self.append("e.csv", stats("hetero", 3.0, compile_s=2.0), count=10)
        _, rows = collect.read_csv(os.path.join(self.d, "e.csv"))
        self.assertAlmostEqual(float(rows[0]["time_s"]), 1.0)
        self.assertEqual(rows[0]["rays_primary"], "10")
        self.assertEqual(rows[0]["workers_1_busy_s"], "0.2")

    def test_union_header(self):
        path = os.path.join(self.d, "u.csv")
        collect.append_row(path, {"a": "1"})
        collect.append_row(path, {"a": "2", "b": "3"})
        header, rows = collect.read_csv(path)
        self.assertEqual(header, ["a", "b"])
        self.assertEqual([r["b"] for r in rows], ["", "3"])

    def test_advantage_from_medians(self):
        for t in (1.0, 1.2, 5.0):        # median 1.2 (5.0 an outlier)
            self.append("e.csv", stats("homo", t), count=10, occ_target=50, seed=1)
        for t in (0.9, 0.6, 0.95):       # median 0.9
            self.append("e.csv", stats("hetero", t), count=10, occ_target=50, seed=1)
        _, rows = collect.read_csv(os.path.join(self.d, "e.csv"))
        (s,) = collect.summarize(rows)
        self.assertAlmostEqual(s["homo_time_s"], 1.2)
        self.assertAlmostEqual(s["hetero_time_s"], 0.9)
        self.assertAlmostEqual(s["advantage_pct"], 25.0)
        self.assertAlmostEqual(s["advantage_min_pct"], 40.0)

    def test_configs_kept_apart(self):
        for n in (10, 20):
            self.append("e.csv", stats("homo", 1.0), count=n, occ_target=50, seed=1)
            self.append("e.csv", stats("hetero", 0.5 if n == 10 else 2.0), count=n,
                        occ_target=50, seed=1)
        _, rows = collect.read_csv(os.path.join(self.d, "e.csv"))
        adv = {s["count"]: s["advantage_pct"] for s in collect.summarize(rows)}
        self.assertEqual(adv, {"10": 50.0, "20": -100.0})

    def test_time_excludes_opencl_setup(self):
        st = stats("hetero", 3.0, compile_s=1.0)
        st["cl_setup_s"] = 0.5
        self.append("e.csv", st, count=10)
        _, rows = collect.read_csv(os.path.join(self.d, "e.csv"))
        self.assertAlmostEqual(float(rows[0]["time_s"]), 1.5)

    def test_paired_rounds(self):
        # Two jobs of two rounds; job 2 round 1 disturbed (homo slow).
        times = {(1, 1): (1.0, 0.9), (1, 2): (1.0, 1.1), (2, 1): (2.0, 0.9), (2, 2): (1.0, 0.8)}
        for (job, rep), (h, g) in times.items():
            for mode, t in (("homo", h), ("hetero", g)):
                self.append("e.csv", stats(mode, t), count=10, occ_target=50, seed=1,
                            job=job, repeat=rep)
        _, rows = collect.read_csv(os.path.join(self.d, "e.csv"))
        (s,) = collect.summarize(rows)
        self.assertEqual(s["rounds"], 4)
        self.assertEqual(s["jobs"], 2)
        # rounds: +10, -10, +55, +20 -> median 15, spread -10 .. 55
        self.assertAlmostEqual(s["adv_paired_pct"], 15.0)
        self.assertAlmostEqual(s["adv_lo_pct"], -10.0)
        self.assertAlmostEqual(s["adv_hi_pct"], 55.0)
        self.assertAlmostEqual(s["adv_job_lo_pct"], 0.0)   # job 1: median of +10, -10
        self.assertAlmostEqual(s["adv_job_hi_pct"], 37.5)  # job 2: median of +55, +20
        self.assertFalse(s["hetero_slower"])
        self.assertAlmostEqual(s["adv_pct"], 15.0)

    def test_slower_in_every_round(self):
        for rep in (1, 2, 3):
            self.append("e.csv", stats("homo", 1.0), count=10, job=1, repeat=rep)
            self.append("e.csv", stats("hetero", 1.2 + rep / 100), count=10, job=1, repeat=rep)
        _, rows = collect.read_csv(os.path.join(self.d, "e.csv"))
        (s,) = collect.summarize(rows)
        self.assertTrue(s["hetero_slower"])
        self.assertIn("slower in every round", collect.spread_cell(s))

    def test_schedules_kept_apart(self):
        for sched, g in (("raster", 0.5), ("tail", 2.0)):
            self.append("e.csv", stats("homo", 1.0), count=10, sched_arg=sched)
            self.append("e.csv", stats("hetero", g), count=10, sched_arg=sched)
        _, rows = collect.read_csv(os.path.join(self.d, "e.csv"))
        adv = {s["sched_arg"]: s["advantage_pct"] for s in collect.summarize(rows)}
        self.assertEqual(adv, {"raster": 50.0, "tail": -100.0})

    def test_run_sh_refuses_code_in_only(self):
        run = os.path.join(os.path.dirname(os.path.abspath(__file__)), "run.sh")
        marker = os.path.join(self.d, "pwned")
        for only in (f"objects\"); open('{marker}', 'w'); (\"",
                     f"objects,$(touch {marker})", "objects,nosuch", ""):
            p = subprocess.run(["bash", run, "--report", "--only", only],
                               capture_output=True, text=True,
                               env=dict(os.environ, BENCH_OUT=self.d, BENCH_WORK=self.d))
            self.assertEqual(p.returncode, 2, (only, p.stderr))
            self.assertFalse(os.path.exists(marker))

    def test_idiff_parse(self):
        path = os.path.join(self.d, "idiff.txt")
        with open(path, "w") as f:
            f.write('Comparing "a.png" and "b.png"\n  Mean error = 0.000132043\n'
                    "  RMS error = 0.00311104\n  Peak SNR = 50.1419\n"
                    "  Max error  = 0.290196 @ (308, 92, R)\n"
                    "  193 pixels (0.131%) over 0.05\n  193 pixels (0.131%) over 0.05\nFAILURE\n")
        buf = io.StringIO()
        with redirect_stdout(buf):
            collect.cmd_idiff([path])
        kv = dict(w.split("=") for w in buf.getvalue().split())
        self.assertEqual(kv["psnr"], "50.1419")
        self.assertEqual(kv["px_over_pct"], "0.131")
        self.assertEqual(kv["mean_err"], "0.000132043")

    def test_report_fills_template(self):
        for n in (10, 50):
            for mode, t in (("homo", 1.0), ("hetero", 0.8 if n == 50 else 1.1)):
                self.append("objects.csv", stats(mode, t, primary=0.1 if mode == "hetero" else 0),
                            count=n, occ_target=20, seed=1, width=384)
        tpl = os.path.join(self.d, "t.md")
        with open(tpl, "w") as f:
            f.write("{{headline}}\n{{objects_table}}\n{{why_table}}\n{{nothing}}\n")
        out = os.path.join(self.d, "R.md")
        collect.cmd_report([self.d, tpl, out])
        text = collect.read_text(out)
        self.assertIn("-10.0% -> 20.0% with 10 objects -> 50 objects", text)
        self.assertIn("(not run)", text)
        self.assertNotIn("{{", text)
        with open(os.path.join(self.d, "objects.dat")) as f:
            self.assertEqual(f.readline().split(), ["count", "occ20"])


if __name__ == "__main__":
    unittest.main()
