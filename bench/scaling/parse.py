#!/usr/bin/python3
"""bench/scaling: parse.py OUT.md LOGDIR CONTENDERS
Logs are LOGDIR/log.<system>.<N>.<repeat>.<contender>. Per system and
contender: median time per step over the repeats with its spread (min..max),
the median over repeats of the ratio to the baseline (the first contender of
CONTENDERS) measured in the same repeat, collisions per step, and the cost per
collision (t - t_baseline) / collisions, in units of the baseline's time per
step and in microseconds."""
import glob, os, re, subprocess, sys, datetime
import numpy as np

out, logdir, contfile = sys.argv[1:4]
order = [l.split()[0] for l in open(contfile) if l.strip() and not l.startswith("#")]
base = order[0]

def parse(path):
    txt = open(path).read()
    loops = re.findall(r"Loop time of (\S+) on (\d+) procs for (\d+) steps with (\d+) atoms", txt)
    if not loops:
        return None
    t, np_, n, nat = loops[-1]
    m = re.search(r"^BENCH collisions (\S+) force_evals (\S+)", txt, re.M)
    coll, fev = (float(m.group(1)), float(m.group(2))) if m else (np.nan, np.nan)
    cpu = re.findall(r"([\d.]+)% CPU use", txt)
    # (in.run's warmup: an untimed run of the same process before the timed one)
    warm = int(loops[0][2]) if len(loops) > 1 else 0
    return dict(tps=float(t) / int(n), n=int(n), warm=warm, natoms=int(nat), coll=coll / int(n),
                fev=fev / int(n), cpu=float(cpu[-1]) if cpu else np.nan)

runs = {}    # (system, N) -> contender -> repeat -> result
for p in glob.glob(os.path.join(logdir, "log.*")):
    parts = os.path.basename(p).split(".")
    if len(parts) != 5:
        continue
    _, sysname, N, k, name = parts
    r = parse(p)
    if r:
        runs.setdefault((sysname, int(N)), {}).setdefault(name, {})[int(k)] = r

def machine():
    model = "?"
    try:
        for line in subprocess.run(["lscpu"], capture_output=True, text=True).stdout.splitlines():
            if line.startswith("Model name"):
                model = line.split(":", 1)[1].strip()
    except OSError:
        pass
    return model, os.cpu_count(), datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")

model, ncpu, date = machine()
L = ["## bench/scaling results", "",
     f"Machine: {model}, nproc {ncpu} (shared, runs under nice), {date}. Serial runs.", "",
     "| system | N | contender | repeats | steps/run | ms/step median (min..max) | "
     f"ratio to {base} median (min..max) | collisions/step | extra force evals/step | "
     f"cost/collision [{base} steps] | cost/collision [us] | CPU use % (min) |",
     "|---|---|---|---|---|---|---|---|---|---|---|---|"]
for key in sorted(runs, key=lambda k: (k[0] != "fluid", k[1])):
    cont = runs[key]
    if base not in cont:
        continue
    for name in [c for c in order if c in cont]:
        reps = cont[name]
        ks = sorted(reps)
        t = np.array([reps[k]["tps"] for k in ks])
        rat = np.array([reps[k]["tps"] / cont[base][k]["tps"] for k in ks if k in cont[base]])
        coll = np.median([reps[k]["coll"] for k in ks])
        fev = np.median([reps[k]["fev"] for k in ks])
        tb = np.median([cont[base][k]["tps"] for k in cont[base]])
        if name != base and coll > 0:
            cpc = (np.median(t) - tb) / coll
            cpc_s = f"{cpc / tb:.3g} | {cpc * 1e6:.3g}"
        else:
            cpc_s = "- | -"
        cpu = min(reps[k]["cpu"] for k in ks)
        w = reps[ks[0]]["warm"]
        steps = f"{reps[ks[0]]['n']}" + (f" (after {w})" if w else "")
        L.append(f"| {key[0]} | {key[1]} | {name} | {len(ks)} | {steps} | "
                 f"{1e3*np.median(t):.3f} ({1e3*t.min():.3f}..{1e3*t.max():.3f}) | "
                 f"{np.median(rat):.3f} ({rat.min():.3f}..{rat.max():.3f}) | "
                 f"{coll:.3g} | {fev:.3g} | {cpc_s} | {cpu:.0f} |")
L += ["",
      f"ratio: time per step over {base}'s in the same repeat (runs alternate contenders), "
      "median over repeats. cost/collision: (median time per step - "
      f"{base}'s) / collisions per step. Collisions from f_hs[1], extra force "
      "evaluations from f_hs[5] (cumulative over the timed run; the fix is defined "
      "fresh in each run). steps/run (after W): the timed run followed W untimed steps "
      "in the same process (run.sh's WARMUP). CPU use below ~95% means the shared machine took cycles "
      "from that run."]
text = "\n".join(L)
open(out, "w").write(text + "\n")
print(text)
