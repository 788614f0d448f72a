#!/usr/bin/python3
"""Markdown tables for benchmarks/RESULTS.md from the JSON in benchmarks/results/, the
target check, and docs/scaling.png (cost per particle against particle count).
Usage: benchmarks/tables.py [LABEL ...]   (default: every label with results, e.g. openmp1)"""
import glob
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from suite import stop_label  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS = os.path.join(ROOT, "benchmarks", "results")

# targets of issue 5
MATVEC_3D_NS = 25          # 3D PPE mat-vec, ns per particle, 2-core CPU
SWEEP_SPEEDUP = 1.8        # OpenMP 2 threads over Serial, neighbour sweeps
DAM_BREAK_3D_SECONDS = 180  # 3D dam break, a = 5 cm, dx = 3 mm, to T = 3
GPU_MATVEC_3D_NS = 1.5      # 3D PPE mat-vec on an H100, ns per particle
GPU_BYTES_PER_PARTICLE = 400


def load(prefix, labels):
    """{label: records} for benchmarks/results/<prefix>_<label>.json."""
    out = {}
    for path in sorted(glob.glob(os.path.join(RESULTS, f"{prefix}_*.json"))):
        label = os.path.basename(path)[len(prefix) + 1:-len(".json")]
        if labels and label not in labels:
            continue
        with open(path) as f:
            out[label] = json.load(f)
    return out


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(lines)


def fmt(v, spec):
    return "—" if v is None else format(v, spec)


def ns(v):
    """A time in ns: whole numbers from 10 up, two significant digits below (GPU)."""
    return f"{v:.0f}" if v >= 10 else f"{v:.2g}"


def suite_tables(labels):
    for label, data in load("suite", labels).items():
        m = data["machine"]
        where = m["gpu"] if "gpu" in m else f"{m['cpu']}, {m['cores']} cores"
        print(f"\n#### Scene suite, `{label}` ({where})\n")
        rows = []
        for r in data["runs"]:
            if r["exit_code"] != 0:
                rows.append([r["case"], f"{r['resolution']:g}", stop_label(r), "failed",
                             f"exit {r['exit_code']}: {r.get('error', '')[:60]}", "", "", "", "", "", "", "",
                             fmt(r["other_load"], ".2f")])
                continue
            st = r["stage_seconds"]
            total = sum(st.values()) or 1
            ppe = st.get("pressure_poisson", 0) / total
            nb = st.get("neighbors", 0) / total
            rows.append([
                r["case"], f"{r['resolution']:g}", stop_label(r), r["particles"],
                r["steps"], f"{r['wall_seconds']:.1f}", f"{r['cg_iterations_mean']:.0f}",
                f"{r['ns_per_particle_step']:.0f}", fmt(r.get("pair_interactions_per_second"), ".3g"),
                f"{fmt(r.get('front_rms_deviation_T1_3'), '.4f')} / {fmt(r.get('front_rms_deviation_T1_3_after_lag'), '.4f')}",
                fmt(r.get("density_error_p95"), ".4f"),
                f"{100 * ppe:.0f} % / {100 * nb:.0f} %", fmt(r.get("memory_bytes_per_particle"), ".0f"),
                fmt(r["other_load"], ".2f")])
        print(table(["case", "a/dx", "CG stop", "particles", "steps", "wall s", "CG it/step",
                     "ns/particle-step", "pairs/s", "front RMS / after lag", "density p95",
                     "PPE / neighbours share", "bytes/particle", "other load"], rows))
        cmds = sorted({r["command"].split(" --out ")[0] for r in data["runs"]})
        print("\nCommands (one per run, with `--out DIR --quiet --set ...` as listed in the JSON): "
              + "; ".join(f"`{c}`" for c in cmds))


def ppe_tables(labels):
    data = load("pressure_poisson", labels)
    rows, solves = [], []
    for label, recs in data.items():
        for r in recs:
            per_unknown = r["n"] / r["unknowns"]
            rows.append([r["backend"], r["threads"], f"{r['dim']}D", f"{r['n']:,}", f"{r['unknowns']:,}",
                         f"{r['nonzeros_per_unknown']:.0f}",
                         ns(r['matvec_cell_ns_per_particle']), ns(r['matvec_list_ns_per_particle']),
                         f"{r['matvec_csr_ns_per_particle']:.1f} ({r['matvec_csr_ns_per_particle'] * per_unknown:.1f})",
                         ns(r['matvec2_list_ns_per_particle']), f"{r['matvec2_csr_ns_per_particle']:.1f}",
                         ns(r['csr_build_ns_per_particle']),
                         f"{r['csr_bytes_per_second'] / 1e9:.1f} / {r['triad_bytes_per_second'] / 1e9:.1f}"])
            if "solve_single_s" in r:
                solves.append([r["backend"], r["threads"], f"{r['dim']}D", f"{r['n']:,}",
                               f"{r['solve_single_s']:.3f} ({r['solve_single_iterations']})",
                               f"{r['solve_two_rhs_s']:.3f} ({r['solve_two_rhs_iterations']})",
                               f"{r['solve_two_single_s']:.3f}",
                               f"{r['solve_two_single_s'] / r['solve_two_rhs_s']:.2f}",
                               f"{r['solve_csr_s']:.3f}", f"{r['solve_single_s'] / r['solve_csr_s']:.1f}",
                               f"{r['eigen_s']:.3f} ({r['eigen_iterations']}, {r['eigen_threads']}t)",
                               f"{r['eigen_over_ours']:.2f}", f"{r['eigen_max_relative_difference']:.1e}"])
    print("\n#### PPE mat-vec, ns per particle (median)\n")
    print(table(["backend", "threads", "dim", "particles", "unknowns", "nonzeros/row", "cell", "list",
                 "csr (per unknown)", "list, 2 rhs", "csr, 2 rhs", "csr build", "csr GB/s / triad GB/s"], rows))
    print("\n#### PPE solves, seconds (CG iterations), tolerance 1e-8\n")
    print(table(["backend", "threads", "dim", "particles", "one rhs", "two rhs at once", "two single",
                 "singles / two", "one rhs, csr", "list / csr", "Eigen CG", "Eigen / ours",
                 "max |ours - Eigen| / max |P|"], solves))


def neighbor_table(labels):
    rows = []
    for label, recs in load("neighbor_search", labels).items():
        for r in recs:
            rows.append([r["backend"], r["threads"], f"{r['dim']}D", f"{r['n']:,}", f"{r['pairs_per_particle']:.0f}",
                         ns(r['bin_ns_per_particle']), ns(r['sweep_ns_per_particle']),
                         ns(r['list_build_ns_per_particle']), ns(r['list_sweep_ns_per_particle'])])
    print("\n#### Binning and neighbour sweeps, ns per particle (median of 5)\n")
    print(table(["backend", "threads", "dim", "particles", "pairs / particle", "bin", "cell sweep",
                 "list build", "list sweep"], rows))


def records(prefix, labels):
    return [r for recs in load(prefix, labels).values() for r in recs]


def scaling_plot(labels):
    """ns per particle against n for the kernels, one panel per dimension."""
    ns, ppe = records("neighbor_search", labels), records("pressure_poisson", labels)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.4), sharey=True)
    series = [(ns, "sweep_ns_per_particle", "cell sweep (density)"),
              (ns, "list_sweep_ns_per_particle", "list sweep (density)"),
              (ppe, "matvec_list_ns_per_particle", "PPE mat-vec, list"),
              (ppe, "matvec_csr_ns_per_particle", "PPE mat-vec, csr")]
    for dim, ax in zip((2, 3), axes):
        for k, (recs, key, name) in enumerate(series):
            for m, (backend, threads) in enumerate(sorted({(r["backend"], r["threads"]) for r in recs})):
                pts = sorted((r["n"], r[key]) for r in recs
                             if r["dim"] == dim and r["backend"] == backend and r["threads"] == threads)
                if pts:
                    x, y = zip(*pts)
                    ax.plot(x, y, ["-o", "--s", ":^"][m % 3], color=f"C{k}", ms=5,
                            label=f"{name}, {backend} {threads}t")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("particles")
        ax.set_title(f"{dim}D", fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("ns per particle")
    axes[1].legend(fontsize=6, ncol=2)
    fig.suptitle("Cost per particle of one sweep against problem size", fontsize=10)
    fig.tight_layout()
    png = os.path.join(ROOT, "docs", "scaling.png")
    fig.savefig(png, dpi=120)
    plt.close(fig)
    print(f"\n(wrote {os.path.relpath(png, ROOT)})")


def targets(labels):
    print("\n#### Targets\n")
    rows = []
    ppe = [r for r in records("pressure_poisson", labels) if r["dim"] == 3 and r["backend"] != "Serial"]
    best = {}
    for r in ppe:
        if r["threads"] == 2:
            best[r["n"]] = r
    for n, r in sorted(best.items()):
        per_unknown = r["n"] / r["unknowns"]
        for key, name in (("matvec_list_ns_per_particle", "list (matrix_free)"),
                          ("matvec_csr_ns_per_particle", "stored coefficients (solver default)")):
            v = r[key]
            rows.append([f"3D PPE mat-vec, {name}, {n:,} particles, 2 threads", f"<= {MATVEC_3D_NS} ns/particle",
                         f"{v:.1f} ({v * per_unknown:.1f} per unknown)",
                         "met" if v <= MATVEC_3D_NS else f"{v / MATVEC_3D_NS:.1f}x over"])
    for r in sorted((r for r in ppe if r["backend"] == "Cuda"), key=lambda r: r["n"]):
        for key, name in (("matvec_list_ns_per_particle", "list (matrix_free)"),
                          ("matvec_csr_ns_per_particle", "stored coefficients (solver default)")):
            v = r[key]
            rows.append([f"3D PPE mat-vec, {name}, {r['n']:,} particles, CUDA", f"<= {GPU_MATVEC_3D_NS} ns/particle",
                         f"{v:.2f}", "met" if v <= GPU_MATVEC_3D_NS else f"{v / GPU_MATVEC_3D_NS:.1f}x over"])
    sweeps = records("neighbor_search", labels)
    for key, name in (("sweep_ns_per_particle", "cell sweep"), ("list_sweep_ns_per_particle", "list sweep")):
        for dim in (2, 3):
            serial = {r["n"]: r[key] for r in sweeps if r["backend"] == "Serial" and r["dim"] == dim}
            omp2 = {r["n"]: r[key] for r in sweeps if r["backend"] == "OpenMP" and r["threads"] == 2 and r["dim"] == dim}
            for n in sorted(set(serial) & set(omp2)):
                s = serial[n] / omp2[n]
                rows.append([f"OpenMP 2 threads / Serial, {name}, {dim}D, {n:,}", f">= {SWEEP_SPEEDUP}",
                             f"{s:.2f}", "met" if s >= SWEEP_SPEEDUP else f"{SWEEP_SPEEDUP - s:.2f} short"])
    memory_rows = set()
    for label, data in load("suite", labels).items():
        for r in data["runs"]:
            if r["case"] == "dam_break_3d" and abs(r["spacing"] - 0.003) < 1e-9 and r["exit_code"] == 0:
                w = r["wall_seconds"]
                rows.append([f"3D dam break dx = 3 mm to T = 3, {label}, CG {stop_label(r)}",
                             f"<= {DAM_BREAK_3D_SECONDS} s", f"{w:.3g} s ({r['steps']} steps)",
                             "met" if w <= DAM_BREAK_3D_SECONDS else f"{w / DAM_BREAK_3D_SECONDS:.1f}x over"])
                if r.get("backend") == "Cuda" and (label, r["particles"]) not in memory_rows:
                    memory_rows.add((label, r["particles"]))
                    b = r["memory_bytes_per_particle"]
                    rows.append([f"memory, 3D dam break dx = 3 mm ({r['particles']:,} particles), {label}",
                                 f"<= {GPU_BYTES_PER_PARTICLE} B/particle", f"{b} B/particle",
                                 "met" if b <= GPU_BYTES_PER_PARTICLE else f"{b / GPU_BYTES_PER_PARTICLE:.1f}x over"])
    print(table(["target", "goal", "measured", "gap"], rows))


def main():
    labels = sys.argv[1:]
    suite_tables(labels)
    ppe_tables(labels)
    neighbor_table(labels)
    targets(labels)
    scaling_plot(labels)


if __name__ == "__main__":
    main()
