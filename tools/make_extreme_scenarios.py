#!/usr/bin/env python3
# Writes the extreme-input scenarios of assets/scenarios/extreme/ (issue 8, docs/hardening.md):
#   python3 tools/make_extreme_scenarios.py   (from the repository root)
import json, math
PI = math.pi
LR = 160 * PI / 180
def pw(points):
    """piecewise-linear signal from (t, value) points"""
    def f(t):
        if t <= points[0][0]: return points[0][1]
        for (t0, v0), (t1, v1) in zip(points, points[1:]):
            if t <= t1: return v0 + (v1 - v0) * (t - t0) / (t1 - t0)
        return points[-1][1]
    return f, [p[0] for p in points]
def swing(t0, t1, half_period, amp, start_sign=1):
    pts = [(t0, 0.0)]
    t = t0 + half_period / 2; s = start_sign
    while t < t1:
        pts.append((round(t, 6), s * amp)); s = -s; t += half_period
    pts.append((t1, 0.0))
    return pts
def scenario(name, desc, duration, signals, notes={}, overrides=None):
    times = sorted(set(round(t, 6) for sig in signals.values() for t in sig[1] if t <= duration) | {0.0})
    script = []
    for t in times:
        k = {"t_s": t}
        for key in ["insertion_m", "rotation_rad", "knob_updown_rad", "knob_leftright_rad"]:
            v = signals[key][0](t) if key in signals else 0.0
            lim = PI if key == 'knob_updown_rad' else (LR if key == 'knob_leftright_rad' else 1e9)
            v = max(-lim, min(lim, v))
            k[key] = 0.0 if abs(v) < 1e-12 else v
        if t in notes: k["note"] = notes[t]
        script.append(k)
    sc = {"format": "colosim-scenario", "version": 1, "name": name, "description": desc,
          "anatomy": "anatomy/adult.json", "params": "params/default.json", "dt_s": 0.001,
          "duration_s": duration, "seed": 1, "start": {"kind": "rest"}, "script": script}
    if overrides: sc = {**{k: v for k, v in sc.items() if k != "script"}, "overrides": overrides, "script": script}
    with open(f"assets/scenarios/extreme/{name}.json", "w") as f:
        f.write("{\n")
        items = [(k, v) for k, v in sc.items() if k != "script"]
        for k, v in items: f.write(f"  {json.dumps(k)}: {json.dumps(v)},\n")
        f.write('  "script": [\n')
        f.write(",\n".join("    " + json.dumps(k) for k in script))
        f.write("\n  ]\n}\n")
# 1. push at 1 m/s from the anus to the colon's length, then keep the scope there.
scenario("extreme_push", "Hardening (issue 8): the scope pushed at 1 m/s from the anus to 1.55 m (the colon's rest length; a clinician advances at ~1-3 cm/s), then held there. Must stay finite with bounded energy.",
         2.0, {"insertion_m": pw([(0, 0), (1.55, 1.55)])}, {1.55: "1.55 m in: held"})
# 2. spin 10 turns a second, one way then the other.
W = 10 * 2 * PI
scenario("extreme_spin", "Hardening (issue 8): the scope pushed at 1 m/s to 0.4 m (the sigmoid), then the handle spun at 10 turns per second (62.8 rad/s) clockwise for 1 s and anticlockwise for 0.5 s.",
         2.0, {"insertion_m": pw([(0, 0), (0.4, 0.4)]),
               "rotation_rad": pw([(0, 0), (0.4, 0), (1.4, W), (1.9, W / 2)])}, {0.4: "spinning starts", 1.4: "reverse"})
# 3. knobs end to end: up/down +-180 deg every 50 ms, left/right +-160 deg every 80 ms,
#    then both slammed from stop to stop within one step, ten times.
ud = swing(0.3, 1.1, 0.05, PI)
lr = swing(0.3, 1.1, 0.08, LR, -1)
slam_ud = [(1.1, 0.0)]; slam_lr = [(1.1, 0.0)]; t = 1.15; s = 1
for i in range(10):
    slam_ud += [(round(t, 6), -s * PI), (round(t + 0.001, 6), s * PI)]
    slam_lr += [(round(t, 6), s * LR), (round(t + 0.001, 6), -s * LR)]
    s = -s; t += 0.03
slam_ud.append((round(t, 6), 0.0)); slam_lr.append((round(t, 6), 0.0))
scenario("extreme_knobs", "Hardening (issue 8): the scope pushed at 1 m/s to 0.3 m, then both knobs swung end to end (up/down +-180 deg every 50 ms, left/right +-160 deg every 80 ms), then slammed from stop to stop within one 1 ms step, ten times.",
         1.6, {"insertion_m": pw([(0, 0), (0.3, 0.3)]),
               "knob_updown_rad": pw(ud + slam_ud[1:]), "knob_leftright_rad": pw(lr + slam_lr[1:])},
         {0.3: "knobs swing", 1.15: "knobs slammed stop to stop in one step"})
# 4. everything at once: in at 1 m/s and out at 1 m/s, spinning 10 turns/s, knobs swinging.
scenario("extreme_all", "Hardening (issue 8): everything at once: the scope pushed in at 1 m/s to 1.55 m and pulled out at 1 m/s, the handle spinning at 10 turns per second (reversing every 0.5 s) and both knobs swinging end to end (every 50 and 80 ms) the whole time.",
         3.2, {"insertion_m": pw([(0, 0), (1.55, 1.55), (3.1, 0.0)]),
               "rotation_rad": pw([(0, 0), (0.5, W / 2), (1.0, 0), (1.5, W / 2), (2.0, 0), (2.5, W / 2), (3.0, 0)]),
               "knob_updown_rad": pw(swing(0.0, 3.1, 0.05, PI)), "knob_leftright_rad": pw(swing(0.0, 3.1, 0.08, LR, -1))},
         {1.55: "1.55 m in: withdrawing"})
# 5. the grip: pushed at 1 m/s against sticky walls (friction coefficient 1): the handle
#    force reaches ScopeParams::max_handle_force_N and the grip slips, both ways (see
#    docs/hardening.md: pushing, and pulled in at the anus after segments join).
scenario("extreme_jam", "Hardening (issue 8): the scope pushed at 1 m/s to 1.2 m against sticky walls (friction coefficient 1): the handle force reaches the grip's limit (100 N) and the grip slips (the actual insertion differs from the command).",
         1.2, {"insertion_m": pw([(0, 0), (1.2, 1.2)])}, {}, {"wall_friction": 1.0})
