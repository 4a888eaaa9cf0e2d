#!/usr/bin/env bash
# The ARGoS round trip for one kind: fit the shipped logs (data/raw/KIND) with epuck2-fit, record
# the protocol in ARGoS with the calibrated plug-in and that coefficient file, refit the recorded
# logs, and check that every coefficient comes back (compare_coefficients.py). default_KIND
# records with the E-Puck2 plug-in's own implementations and checks for its published
# coefficients.
#   usage: roundtrip.sh KIND EPUCK2_FIT ARGOS_LIBDIR WORK_DIR
# Exit 77 (CTest: skipped) when argos3 is not installed.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
KIND="$1"; FIT="$2"; LIBDIR="$3"; WORK="$4/$1"
if ! command -v argos3 >/dev/null 2>&1; then echo "SKIPPED: argos3 is not installed"; exit 77; fi
export EPUCK2_BUILD_DIR="$(dirname "$(dirname "$LIBDIR")")"
rm -rf "$WORK"; mkdir -p "$WORK/recorded"
run() { echo "+ $*"; "$@"; }
case "$KIND" in
  default_*)
    kind="${KIND#default_}"
    fitkind="$kind"
    run "$ROOT/scripts/argos-record.sh" "$kind" default "$WORK/recorded"
    run "$FIT" "$fitkind" "$WORK"/recorded/*.csv -o "$WORK/refit.json" > "$WORK/refit.txt"
    run python3 "$HERE/compare_coefficients.py" "$kind" "$WORK/refit.json" plugin
    ;;
  battery)
    # Recorded with behaviour="corrected". With the plug-in's arithmetic (its own models, or
    # behaviour="argos") the run's starting level is the table of the FIRST tick's speed: from a
    # full charge the plug-in drops to that table's d at once, and dynamics2d gives the spinning
    # robot 90 % of its command on the first tick (10 cm/s reads 9.00), so a run at s cm/s follows
    # table s shifted in time whenever table s-1 starts lower: the refit then misses d at 10, 12,
    # 13 and 14 cm/s (by 2-3 standard errors). docs/argos.md, "The battery round trip".
    # One dynamics2d step per tick (EPUCK2_ARGOS_ITERATIONS=1; the experiment has 10): robots
    # spinning in place need no finer steps, and the ten were 90 % of the recording's time (10 s
    # of CPU, now 2 s). Every refit coefficient against the same tolerances: the largest |diff| is
    # 0.58 of its tolerance either way, the mean 0.156 against 0.155 with ten steps.
    export EPUCK2_BATTERY_BEHAVIOUR=corrected EPUCK2_BATTERY_MODEL=cubic EPUCK2_ARGOS_ITERATIONS=1
    run "$FIT" battery "$ROOT"/data/raw/battery/*.csv -o "$WORK/fitted.json" > "$WORK/fitted.txt"
    run "$ROOT/scripts/argos-record.sh" battery "$WORK/fitted.json" "$WORK/recorded"
    run "$FIT" battery "$WORK"/recorded/*.csv -o "$WORK/refit.json" > "$WORK/refit.txt"
    run python3 "$HERE/compare_coefficients.py" battery "$WORK/refit.json" "$WORK/fitted.json"
    ;;
  camera)
    # The camera round trip against a known truth, with the calibrated pixel noise on: the file's
    # noise.camera.sd (0.58 px, measured) dithers ARGoS's whole-pixel rounding as a real camera's
    # noise does, so the refit's mean is the sub-pixel projection's (noiseless, every frame of a
    # grid position rounds the same way and that bias is not averaged out). Truth: the shipped
    # fit's fov_deg and noise, the centre moved off whole pixels (80.37, 60.62); 20 frames at each
    # of the grid's 190 positions, seeded. pinhole.json is recorded and refitted with `epuck2-fit
    # camera`; distorted.json adds radial_distortion k1 = -0.3 (a diagnosis effect), recorded and
    # refitted with `epuck2-fit diagnose --kind camera` on the pinhole refit. Each parameter must
    # come back within 2 of the refit's own standard errors (compare_coefficients.py --own-se 2).
    export EPUCK2_ARGOS_NOISE=true EPUCK2_ARGOS_SAMPLES=20 EPUCK2_ARGOS_SEED=124
    python3 - "$ROOT/data/fitted/camera.json" "$WORK" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
d.pop("robots", None)  # one robot: no pooled-set warning
d["parameters"].update({"cx_px": 80.37, "cy_px": 60.62})
d["noise"]["camera"].pop("per_sensor_sd", None)
json.dump(d, open(sys.argv[2] + "/pinhole.json", "w"), indent=1)
d["effects"] = {"radial_distortion": {"k1": -0.3}}
json.dump(d, open(sys.argv[2] + "/distorted.json", "w"), indent=1)
PY
    run "$ROOT/scripts/argos-record.sh" camera "$WORK/pinhole.json" "$WORK/recorded"
    run "$FIT" camera "$WORK"/recorded/*.csv -o "$WORK/refit.json" > "$WORK/refit.txt"
    run python3 "$HERE/compare_coefficients.py" camera "$WORK/refit.json" "$WORK/pinhole.json" --own-se 2
    run "$ROOT/scripts/argos-record.sh" camera "$WORK/distorted.json" "$WORK/recorded_distorted"
    run "$FIT" diagnose --kind camera --coefficients "$WORK/refit.json" "$WORK"/recorded_distorted/*.csv \
        -o "$WORK/diagnosis.json" > "$WORK/diagnosis.txt"
    run python3 "$HERE/compare_coefficients.py" camera "$WORK/diagnosis.json" "$WORK/distorted.json" --own-se 2
    ;;
  *)
    run "$FIT" "$KIND" "$ROOT"/data/raw/"$KIND"/*.csv -o "$WORK/fitted.json" > "$WORK/fitted.txt"
    run "$ROOT/scripts/argos-record.sh" "$KIND" "$WORK/fitted.json" "$WORK/recorded"
    # The refit's pooled curve ("All sensors together", one gamma) misses its replicates: light's
    # by 114 replicate sd, worst at intensity 2.00. That is the truth, not a fault: the file gives
    # sensors 0 and 7 gammas 3 % apart (0.0748 and 0.0726 m), each is recorded with its own, and
    # ARGoS records without noise, so the replicates agree to the rounding (sd 7e-5 of full
    # scale) and any pooled curve misses them by many sd. The per-sensor refits fit (0.8-0.9 sd),
    # and the round trip compares parameters: the misfit is accepted and stays in refit.txt.
    run "$FIT" "$KIND" "$WORK"/recorded/*.csv -o "$WORK/refit.json" --accept-misfit > "$WORK/refit.txt"
    run python3 "$HERE/compare_coefficients.py" "$KIND" "$WORK/refit.json" "$WORK/fitted.json"
    ;;
esac
