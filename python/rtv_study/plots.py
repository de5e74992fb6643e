"""The study's plots (DIR/plots/): each metric against each parameter, and pass/fail maps over each pair of
numeric parameters where the case judges a pass (a manoeuvre's limits)."""
import re
from pathlib import Path

import numpy as np
import pyarrow as pa


def _file_name(text):
    return re.sub(r"[^A-Za-z0-9]+", "_", text).strip("_")


def plot_study(table, study, folder):
    """Write the plots; returns their paths."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    ok = table.filter(pa.compute.equal(table.column("status"), "ok"))
    numeric = [p.name for p in study.parameters if ok.schema.field(p.name).type == pa.float64()]
    written = []
    passed = "passed" if "passed" in study.metrics else next((m for m in study.metrics if m.startswith("pass:")), None)
    flags = np.array([bool(v) for v in ok.column(passed).to_pylist()]) if passed and ok.num_rows else None
    for metric in study.metrics:
        if metric == passed:
            continue
        y = np.array([np.nan if v is None else float(v) for v in ok.column(metric).to_pylist()])
        for p in numeric:
            x = np.array(ok.column(p).to_pylist(), dtype=float)
            fig, ax = plt.subplots(figsize=(6, 4))
            if flags is not None:
                ax.scatter(x[flags], y[flags], s=8, c="tab:green", label="pass")
                ax.scatter(x[~flags], y[~flags], s=8, c="tab:red", label="fail")
                ax.legend(fontsize=8)
            else:
                ax.scatter(x, y, s=8)
            ax.set_xlabel(p)
            ax.set_ylabel(metric)
            ax.set_title(f"{study.name}: {metric} against {p} ({ok.num_rows} runs)", fontsize=9)
            ax.grid(alpha=0.3)
            path = folder / f"{_file_name(metric)}__{_file_name(p)}.png"
            fig.tight_layout()
            fig.savefig(path, dpi=110)
            plt.close(fig)
            written.append(path)
    if flags is not None:
        for i, a in enumerate(numeric):
            for b in numeric[i + 1:]:
                x, y = (np.array(ok.column(n).to_pylist(), dtype=float) for n in (a, b))
                fig, ax = plt.subplots(figsize=(6, 4.5))
                ax.scatter(x[flags], y[flags], s=10, c="tab:green", marker="o", label=f"pass ({flags.sum()})")
                ax.scatter(x[~flags], y[~flags], s=10, c="tab:red", marker="x", label=f"fail ({(~flags).sum()})")
                ax.set_xlabel(a)
                ax.set_ylabel(b)
                ax.set_title(f"{study.name}: {passed} ({study.case})", fontsize=9)
                ax.legend(fontsize=8, loc="best")
                ax.grid(alpha=0.3)
                path = folder / f"passfail__{_file_name(a)}__{_file_name(b)}.png"
                fig.tight_layout()
                fig.savefig(path, dpi=110)
                plt.close(fig)
                written.append(path)
    return written
