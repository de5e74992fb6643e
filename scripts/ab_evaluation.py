"""Same-session A/B timing of the evaluation: two builds of examples/evaluation_instructions.rs, run in
alternation (N evaluations, less a run of none, so the set-up is left out), 12 rounds; prints the time per
evaluation from the fastest runs and from the median runs of each. On a noisy machine the fastest runs are the
steadier figure; instruction counts (the example's header) are the repeatable one.

    git worktree add /tmp/old <commit> && (cd /tmp/old && cargo build --release --example evaluation_instructions)
    cargo build --release --example evaluation_instructions
    python3 scripts/ab_evaluation.py /tmp/old target/release/examples/evaluation_instructions \\
        . target/release/examples/evaluation_instructions

Each binary runs in its own checkout (it reads the vehicle data relative to it).
"""
import statistics
import subprocess
import sys
import time

N, ROUNDS = 200_000, 12


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    builds = {"A": (sys.argv[1], sys.argv[2]), "B": (sys.argv[3], sys.argv[4])}
    times = {k: {0: [], N: []} for k in builds}
    for _ in range(ROUNDS):
        for name, (checkout, binary) in builds.items():
            for n in (0, N):
                start = time.perf_counter()
                subprocess.run([binary, str(n)], cwd=checkout, check=True, capture_output=True)
                times[name][n].append(time.perf_counter() - start)
    for name, (checkout, binary) in builds.items():
        t = times[name]
        fastest = (min(t[N]) - min(t[0])) / N * 1e6
        median = (statistics.median(t[N]) - statistics.median(t[0])) / N * 1e6
        print(f"{name} ({checkout}): {fastest:.3f} us per evaluation from the fastest runs, {median:.3f} from the median")


if __name__ == "__main__":
    main()
