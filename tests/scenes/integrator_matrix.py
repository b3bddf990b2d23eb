#!/usr/bin/env python3
"""Every scene under every integrator: no combination may crash or quietly return nonsense (issue 28).
Each runs its scene's own window, but for the scenes in SHORT_WINDOW (minutes a run), which run ten
steps: there the test shows only that the combination starts and steps without a crash, its checks not
evaluated (their whole runs are scene tests under the scene's own integrator, and under ida for
sdnv104-quad8; not under the others). Each one must
  - run and pass every check it can evaluate in the window (checks beyond it are not evaluated), or
  - be refused before the first step by `validate` and `run` alike: exit 2, the same message, naming
    integrator.type, the feature and what to use instead, and no output folder left behind, or
  - be listed in EXPECTED below with the reason it fails its checks or stops.
A listed combination that no longer fails is reported too, so that the list stays true.

usage: integrator_matrix.py CSIM SCENES_DIR WORK_DIR
"""
import json
import os
import shutil
import subprocess
import sys
import time

INTEGRATORS = ["moreau-jean", "quasi-static", "ida", "ida-events", "generalized-alpha"]
WINDOW_STEPS = 10
# rounded-shapes-incline: over two minutes under ida (measured; not investigated); its checks read t.
# terrain-mesh: ida refuses triangle meshes (ida_integrator.cpp).
SHORT_WINDOW = {"rolling-ring", "rolling-ring-3d", "sdnv104-quad8", "rounded-shapes-incline", "terrain-mesh"}

# (scene, integrator) -> why it does not pass, and the outcome it has: "checks" (exit 1, an evaluated
# check fails) or "stops" (exit 2 during the run: a numerical failure with its message).
REGULARIZED = "ida's regularized law: "
EXPECTED = {
    ("rounded-shapes-at-rest", "ida"): ("checks", REGULARIZED + "the penalty layer lets each body sink by m g / (k × its "
                                        "points), 4.9e-8 m, beyond the 1e-9 m checks (the scene test runs ida with "
                                        "sink_tolerance 1e-7)"),
    ("rounded-shapes-incline", "ida"): ("checks", REGULARIZED + "over the short window the rolls lag the closed "
                                        "forms by 1.4e-4 and the normal force is 3e-4 off (penalty and regularized "
                                        "Coulomb), against checks of 1e-9 and 1e-6"),
    ("bouncing-ball", "ida"): ("checks", REGULARIZED + "the penalty dashpot only approximates Newton's restitution "
                               "(regularized_law.h: the no-tension clamp makes the rebound livelier than e)"),
    ("box-on-block", "ida"): ("checks", REGULARIZED + "the box rides on the soft penalty layer of the block "
                              "(0.01 K_ii), its normal force oscillating about m g by about 1 %, and the check reads one sample"),
    ("box-on-block-3d", "ida"): ("checks", REGULARIZED + "the same penalty oscillation (1.3 % on the weight, "
                                 "0.2 % on the slide)"),
    ("box-tower", "ida"): ("checks", REGULARIZED + "the cubes sit on penalty layers and creep: the top corner moves "
                           "by 2e-6 m and the interface forces are off by 1e-6 to 4e-5 relative against exact statics "
                           "checked to 1e-9 m and 1e-8"),
    ("fe-damped-drift", "ida"): ("checks", "the dissipation check's 1e-6 is Moreau-Jean's; IDA at rtol 1e-6 is 6e-6 off "
                                 "(agreement with Moreau-Jean to 1e-3: IdaOnElasticBodies.DampedDriftAgreesWithMoreauJean)"),
    ("fe-free-vibration", "ida"): ("checks", "energy_conserved (1e-10) and balance_closes (1e-9 J) hold the exact "
                                   "conservation of theta = 1/2; BDF dissipates to its tolerance (1e-4 at rtol 1e-8: "
                                   "IdaOnElasticBodies.FreeVibrationKeepsItsEnergyToTheTolerance)"),
    ("incline", "ida"): ("checks", REGULARIZED + "no true stick: the block creeps at epsilon rho / sqrt(1 - rho^2)"),
    ("incline-3d", "ida"): ("checks", REGULARIZED + "the same creep (1e-5 m), and forces off by 1e-9 relative "
                            "against the checks' 1e-10"),
    ("sdnd100-a", "ida"): ("checks", REGULARIZED + "the pad creeps instead of coming to rest on the line"),
    ("sdnd100-d", "ida"): ("checks", REGULARIZED + "the pad creeps instead of coming to rest on the line"),
    ("fe-free-vibration", "generalized-alpha"): ("checks", "energy_conserved (1e-10) holds the exact conservation of "
                                                 "theta = 1/2; generalized-alpha at its default rho_infinity 0.8 damps the "
                                                 "modes the step does not resolve (3.2e-5 of the energy here; at rho_infinity = 1 "
                                                 "it conserves: GeneralizedAlpha.RhoOneIsMoreauJeanThetaOneHalf)"),
    ("neo-hookean-compression", "moreau-jean"): ("checks", "at theta = 1/2 the block's elastic waves are never damped: "
                                                 "the quasi-static closed form holds under moreau-jean with theta = 1 "
                                                 "(scene test neo-hookean-compression-moreau-jean)"),
    ("ssnv503-2d", "moreau-jean"): ("checks", "a quasi-static benchmark: its placeholder density rings under a dynamic "
                                    "integrator at theta = 1/2"),
    ("ssnv503-3d", "moreau-jean"): ("checks", "a quasi-static benchmark: its placeholder density rings under a dynamic "
                                    "integrator at theta = 1/2"),
    ("spinning-bar", "quasi-static"): ("checks", "the bar turns by its inertia alone, which the quasi-static stepper "
                                       "does not have"),
    ("sdnv104-quad4", "quasi-static"): ("stops", "the shoe is held along x by its springs and along y by nothing: "
                                        "its contact opens, the proximal iterates on its free vertical motion do not "
                                        "converge, and the run names the node (quasi_static.h, soft directions)"),
    ("sdnv104-quad8", "quasi-static"): ("stops", "the same free vertical motion as sdnv104-quad4's, refused the same way "
                                        "(its pivot is round-off of either sign: the decision no longer depends on it)"),
    ("stress-block", "quasi-static"): ("checks", "the contact holds the block's vertical motion, so the quasi-static "
                                       "stepper finds the static equilibrium x = (F - mu m g) / k = 0.0294 m; the checks "
                                       "are the dynamic overshoot, twice that"),
    ("hertz-quarter-disk", "moreau-jean"): ("checks", "a quasi-static benchmark: its two 0.5 s steps at theta = 1/2 "
                                            "leave the disk ringing (normal force 0.75 P)"),
}


def run(command):
    result = subprocess.run(command, capture_output=True, text=True, timeout=600)
    return result.returncode, (result.stdout + result.stderr).strip()


def dump_value(csim, scene, key):
    """A number of the effective scene; "=name" is looked up among its parameters."""
    value = dump_text(csim, scene, key).strip()
    if value.startswith("="):
        return float(dump_text(csim, scene, "parameters." + value[1:].strip()))
    return float(value)


def dump_text(csim, scene, key):
    code, text = run([csim, "dump-config", scene])
    section, name = key.split(".")
    inside = False
    for line in text.splitlines():
        if line.startswith(section + ":"):
            inside = True
            rest = line[len(section) + 1:].strip()
            if rest.startswith("{"):  # flow style
                for part in rest.strip("{}").split(","):
                    k, _, v = part.partition(":")
                    if k.strip() == name:
                        return v
            continue
        if inside and line.startswith("  " + name + ":"):
            return line.split(":", 1)[1].split("#")[0]
        if inside and line and not line.startswith(" "):
            inside = False
    raise RuntimeError(f"{scene}: no {key} in dump-config")


def main():
    csim, scenes_dir, work = sys.argv[1:4]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    problems, table = [], []
    for name in sorted(os.listdir(scenes_dir)):
        scene = os.path.join(scenes_dir, name)
        if not os.path.isfile(os.path.join(scene, "scene.yaml")):
            continue
        window = []
        if name in SHORT_WINDOW:
            step = dump_value(csim, scene, "time.step")
            window = ["--set", f"time.end={WINDOW_STEPS * step!r}"]
        for integrator in INTEGRATORS:
            overrides = ["--set", f"integrator.type={integrator}"] + window
            out = os.path.join(work, f"{name}-{integrator}")
            v_code, v_text = run([csim, "validate", scene] + overrides)
            start = time.monotonic()
            r_code, r_text = run([csim, "run", scene, "--quiet", "--out", out] + overrides)
            seconds = time.monotonic() - start
            key = (name, integrator)
            expected = EXPECTED.get(key)
            if r_code < 0 or r_code > 2 or v_code < 0 or v_code > 2:
                outcome = f"SIGNAL or bad exit (validate {v_code}, run {r_code}): {r_text[-300:]}"
                problems.append(f"{name} / {integrator}: {outcome}")
            elif v_code == 2 or (r_code == 2 and not os.path.exists(os.path.join(out, "summary.json"))
                                 and "integrator.type" in r_text):
                outcome = "refused"
                first_line = r_text.splitlines()[0] if r_text else ""
                if v_code != 2 or r_code != 2:
                    problems.append(f"{name} / {integrator}: validate says {v_code}, run says {r_code}")
                elif v_text.splitlines()[0] != first_line:
                    problems.append(f"{name} / {integrator}: validate and run refuse differently:\n  {v_text}\n  {r_text}")
                elif "integrator.type" not in first_line or "use " not in first_line:
                    problems.append(f"{name} / {integrator}: a refusal must name integrator.type and what to use: {first_line}")
                elif os.path.exists(out):
                    problems.append(f"{name} / {integrator}: refused, but left {out} behind")
                outcome += ": " + first_line.split("integrator.type: ", 1)[-1][:110]
            elif r_code == 2:
                outcome = "stops: " + r_text.splitlines()[-1][:160]
                if not expected or expected[0] != "stops":
                    problems.append(f"{name} / {integrator}: {outcome}")
            else:
                with open(os.path.join(out, "summary.json")) as f:
                    checks = json.load(f)["checks"]
                failed = [c["name"] for c in checks if c["evaluated"] and not c["skipped"] and not c["passed"]]
                evaluated = [c["name"] for c in checks if c["evaluated"] and not c["skipped"]]
                if failed:
                    outcome = "fails " + ", ".join(failed)
                    if not expected or expected[0] != "checks":
                        problems.append(f"{name} / {integrator}: {outcome}")
                else:
                    outcome = (f"passes {len(evaluated)} evaluated checks" if evaluated else
                               "runs 10 steps; no check can be judged there (not a pass)")
                    if expected:
                        problems.append(f"{name} / {integrator}: listed as expected to {expected[0]} "
                                        f"({expected[1]}), but {outcome}")
            if expected:
                outcome += f"  [expected: {expected[1]}]"
            table.append(f"{name:26s} {integrator:13s} {seconds:6.1f} s  {outcome}")
    print("\n".join(table))
    for key in EXPECTED:
        if key[0] not in {line.split()[0] for line in table}:
            problems.append(f"{key}: listed, but there is no such scene")
    if problems:
        print("\nPROBLEMS:\n" + "\n".join(problems))
        print(f"\n{len(table) - len(problems)} passed, {len(problems)} failed")
        return 1
    print(f"\n{len(table)} passed, 0 failed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
