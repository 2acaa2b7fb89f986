#!/usr/bin/env python3
"""A stand-in for a slow simulation behind cierva's model interface (protocol
cierva-external/2, persistent mode: docs/external-models.md): every trim takes
`SECONDS_PER_TRIM` of wall time (it sleeps), as a blade-element model taking a second a trim
would. What `reports/benchmarks.md` measures a plan's overhead on: a study whose evaluations
cost a known time, so that the engine's and cierva's overheads show against it.

Synthetic: its trim is a made-up smooth function of its three parameters, whose ranges are
made up too (source "synthetic"); it is evidence of nothing about an aircraft. Standard library
only. `python3 slow_model.py --serve [--seconds S]`.
"""
import json
import os
import sys
import time

PROTOCOL = "cierva-external/2"
# The wall time of one trim, s (a model that takes a second a trim); `--seconds` or the
# environment's SLOW_MODEL_SECONDS sets it (a quick try: 0.01).
SECONDS_PER_TRIM = float(os.environ.get("SLOW_MODEL_SECONDS", "1.0"))

PARAMETERS = [
    {"name": "fin_area_m2", "unit": "m^2", "meaning": "fin area (synthetic)", "nominal": 0.30,
     "range": {"lower": 0.27, "upper": 0.33, "source": "synthetic: +-10 %, made up for the benchmark",
               "distribution": "uniform"}},
    {"name": "drag_area_m2", "unit": "m^2", "meaning": "fuselage drag area (synthetic)", "nominal": 0.50,
     "range": {"lower": 0.45, "upper": 0.55, "source": "synthetic: +-10 %, made up for the benchmark",
               "distribution": "uniform"}},
    {"name": "cg_x_m", "unit": "m", "meaning": "centre of gravity (synthetic)", "nominal": 0.0,
     "range": {"lower": -0.05, "upper": 0.05, "source": "synthetic: +-5 cm, made up for the benchmark",
               "distribution": "uniform"}},
]


def trim(request):
    p = {x["name"]: x["nominal"] for x in PARAMETERS}
    p.update(request.get("parameters") or {})
    v = request["condition"]["airspeed_mph"]
    time.sleep(SECONDS_PER_TRIM)
    return {"pitch_deg": 8.0 - 0.06 * v + 20.0 * p["cg_x_m"] + 0.5 * p["fin_area_m2"],
            "throttle_percent": 40.0 + 0.004 * v * v * p["drag_area_m2"] / 0.5}


def answer(request):
    compute = request.get("compute")
    if compute == "describe":
        return {"describe": {"computes": ["trim"], "parameters": PARAMETERS}}
    if compute == "trim":
        return {"trim": trim(request)}
    return {"error": f"`{compute}` is not provided by this model"}


def main():
    global SECONDS_PER_TRIM
    if "--seconds" in sys.argv:
        SECONDS_PER_TRIM = float(sys.argv[sys.argv.index("--seconds") + 1])
    for line in sys.stdin:
        request = json.loads(line)
        out = {"protocol": PROTOCOL, "id": request.get("id")}
        out.update(answer(request))
        sys.stdout.write(json.dumps(out) + "\n")
        sys.stdout.flush()


main()
