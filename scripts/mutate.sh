#!/usr/bin/env bash
# Mutation testing: does the test suite notice plausible bugs? Each mutant is one small edit of the
# models, the fits or the diagnosis's decision rules (the list below). The script copies the
# checkout into build-mut/src (never edits the checkout itself), builds the test programs once in
# build-mut/src/build (Release, ccache: under the same relative paths as build/, so most objects
# come from the cache), checks that the chosen tests pass unmutated, then for each mutant: applies
# the edit to the copy, rebuilds only the targets the mutant's tests need, runs those tests (ctest
# -R, with a per-mutant timeout), and restores the file. A mutant is killed when a test fails or
# times out, survived when every test passes; one that does not compile is invalid (not counted).
#
#   scripts/mutate.sh                 every mutant
#   scripts/mutate.sh light tof       only the mutants whose name contains one of these words
#   EPUCK2_MUT_TIMEOUT=600 scripts/mutate.sh   per-mutant test timeout in seconds (default 420)
#   scripts/mutate.sh --check         checks the list only (builds and runs nothing): exit 1 naming
#                                     every mutant whose file is missing or whose original text
#                                     does not occur exactly once in it (a stale mutant)
#
# A test group is either (test programs, ctest -R pattern) or whole(programs, extra tests): every
# test those programs define (their names read from `ctest --show-only=json-v1`) and the extra
# tests (prefixes of ctest names, without "|"). A whole group's tests all run (no --stop-on-failure):
# every failing test is printed, and a mutant that only the comparisons of regenerated output fail
# (STABILITY below: they check that output is stable, not that it is right) is marked so.
# EPUCK2_JOBS sets the build's parallelism, EPUCK2_MUT_TEST_JOBS ctest's (default EPUCK2_JOBS).
#
# Prints killed/survived per mutant and the score; exit 0 when the score is >= 90 %.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT="$PWD"
export EPUCK2_MUT_ROOT="$ROOT"
exec /usr/bin/python3 - "$@" <<'PY'
import json, os, shutil, subprocess, sys, time

ROOT = os.environ["EPUCK2_MUT_ROOT"]
MUT = os.path.join(ROOT, "build-mut")
SRC = os.path.join(MUT, "src")
BUILD = os.path.join(SRC, "build")
JOBS = os.environ.get("EPUCK2_JOBS", str(os.cpu_count() or 2))
TIMEOUT = int(os.environ.get("EPUCK2_MUT_TIMEOUT", "420"))
TEST_JOBS = os.environ.get("EPUCK2_MUT_TEST_JOBS", JOBS)
# The comparisons of regenerated output with committed files: a mutant only these fail is caught
# by a stability check, not by a correctness test.
STABILITY = {"SafeCli.TheShippedCoefficientFilesAndReportsRegenerateByteForByte",
             # (the shipped logs against a fresh generation: stable generators, not right ones)
             "VirtualSensors.CommittedLogsAreFresh", "VirtualBattery.CommittedLogsAreFresh",
             "BatteryCli.CommittedHeaderIsWhatCodegenWritesToday", "docs_commands"}

M = "lib/models/include/epuck2/models/sensors.hpp"
ML = "lib/models/include/epuck2/models/light.hpp"
MG = "lib/models/include/epuck2/models/ground.hpp"
MT = "lib/models/include/epuck2/models/tof.hpp"
MP = "lib/models/include/epuck2/models/proximity.hpp"
MC = "lib/models/include/epuck2/models/camera.hpp"
ME = "lib/models/include/epuck2/models/encoders.hpp"
MD = "lib/models/include/epuck2/models/drive.hpp"
B = "lib/models/include/epuck2/models/battery.hpp"
FS_G = "lib/calibrate/src/ground_fit.cpp"
FS_L = "lib/calibrate/src/light_fit.cpp"
FS_D = "lib/calibrate/src/drive_fit.cpp"
FH = "lib/calibrate/include/epuck2/calibrate/sensors.hpp"
DE = "lib/diagnose/src/engine.cpp"
DE_H = "lib/diagnose/src/engine_detail.hpp"
DE_RS = "lib/diagnose/src/residual_structure.cpp"
DE_S = "lib/diagnose/src/search.cpp"
DH = "lib/diagnose/include/epuck2/diagnose/diagnose.hpp"
RB = "lib/fit/src/robust.cpp"
RD = "lib/fit/src/readings.cpp"  # the one censored (Tobit) residual

# Test groups: the test programs to build and the ctest -R pattern of the tests to run.
SENSORS = (["test_sensor_models", "test_sensor_fits", "test_independent_checks", "test_measured_logs"],
           r"^(Sensor|Proximity|Light|Ground|Tof|Encoder|Camera|Drive|Leds|HandComputed|IndependentFit|Measured|RobustEngine|Distributions)")
BATTERY = (["test_battery_models", "test_battery_fit", "test_virtual_robot_battery", "test_independent_checks"],
           r"^(Battery|VirtualBattery|HandComputed)")
DIAGNOSE = (["test_diagnose", "test_independent_checks"],
            r"^(DiagnoseHidden\.(Ground|Light|NoEffect)|DiagnoseGates)")

# Slips planted fresh for issue #22 (bench/fresh-slips.md), in areas the list above missed: the
# firmware's speed cap, the column-unit hints, the diagnosis's ToF codes, the reading-noise estimate.
LR = "lib/logs/src/log.cpp"
LH = "lib/logs/include/epuck2/logs/log.hpp"
DK_GROUND = "lib/diagnose/src/kind_ground.cpp"
DK_PROXIMITY = "lib/diagnose/src/kind_proximity.cpp"
DK_LIGHT = "lib/diagnose/src/kind_light.cpp"
DK_CAMERA = "lib/diagnose/src/kind_camera.cpp"
DK_DRIVE = "lib/diagnose/src/kind_drive.cpp"
DK_BATTERY = "lib/diagnose/src/kind_battery.cpp"
CAP = (["test_sensor_fits", "test_measured_logs", "test_independent_checks", "test_area_boundaries"],
       r"^(DriveFit|Measured|IndependentFit|HandComputed|FirmwareCap)")
HINTS = (["test_log_reader", "test_cli_grammar", "test_area_boundaries"], r"^(LogReader|ReaderCli|Grammar|ColumnUnitHints)")
NOISE = (["test_reading_noise", "test_sensor_fits", "test_measured_logs", "test_area_boundaries"],
         r"^(CalibratedReadingNoise|PooledReplicateSd|ReadingNoise|SensorCoefficientFiles|Measured|NoiseByHand)")
RN = "lib/calibrate/src/reading_noise.cpp"
TOF_CODES = (["test_diagnose_steps", "test_log_reader", "test_measured_logs", "test_sensor_fits", "test_area_boundaries"],
             r"^(DiagnoseBase|DiagnoseSteps|LogReader|MeasuredDrive|DriveFit|DiagnosisTofCodes)")
# The second fresh set (bench/fresh-slips.md, branch unlisted-bugs): the voltage->charge map, the
# cluster-robust errors, the robots' Cochran Q test. (The CLI's tests are not in these groups: the
# mutants' fast build does not relink the CLI.)
CM = "lib/calibrate/src/charge_map.cpp"
SC = "lib/diagnose/src/screening.cpp"
RP = "lib/fit/src/report.cpp"
CHARGE = (["test_charge_map", "test_unlisted_areas"], r"^(ChargeMap|ChargeMapByHand)")
CLUSTER = (["test_report", "test_report_files", "test_measured_logs", "test_unlisted_areas"],
           r"^(Autocorrelation|ClusterRobust|ReportFiles|ReportText|Measured|RobustEngine|ClusterRobustByHand)")
QTEST = (["test_measured_logs", "test_sensor_fits", "test_unlisted_areas"], r"^(Measured|RobustEngine|Sensor|RobotSpreadByHand)")
TOBIT = (SENSORS[0] + ["test_unlisted_areas"], SENSORS[1][:-1] + "|TobitByHand)")
IDENTIFY = (["test_diagnose_steps", "test_unlisted_areas"], r"^(DiagnoseBase|DiagnoseNaming|DiagnoseSteps|IdentifyByHand)")
CG = "lib/coefficients/src/codegen.cpp"
# (test_model_loop also writes headers, through the CLI, which the mutants' fast build does not relink.)
CODEGEN = (["test_coefficients", "test_unlisted_areas"], r"^(CoefficientFile|EffectRegistry|NewEffect|CodegenByHand)")
# Round 2 of the fresh slips (bench/fresh-slips.md, branch fresh-slips-2): each group is its area's
# tests and tests/test_round_two_slips.cpp's suite for it. The simulate --like mutants are in apps/:
# their group names the CLI (epuck2-fit), which the fast build then relinks.
R2 = "test_round_two_slips"


def round_two(group, suite):
    return (group[0] + [R2], group[1][:-1] + "|" + suite + ")")


SLM = "lib/models/include/epuck2/models/simulate_log.hpp"  # simulate --like: each model type on a log's rows
LIKE = (["epuck2-fit", R2], r"^RoundTwoSimulateLike")
MF = "lib/coefficients/src/model_file.cpp"


# Round 3 of the fresh slips (bench/fresh-slips.md, branch fresh-slips-3): each group is every test
# of the test programs that touch the area (and the CLI, relinked, for the programs that run it),
# the comparisons of regenerated output included, so that "killed by the suite" is the suite's
# verdict, not one chosen suite's. (docs_commands is not in them: it copies the checkout with git,
# which the script's copy is not.)
def whole(programs, extra=()):
    return (sorted(set(programs)) + ["epuck2-fit"], ("whole", tuple(sorted(set(programs))), tuple(extra)))


R3_ALWAYS = ["test_safe_cli", "test_round_two_slips", "test_unlisted_areas", "test_area_boundaries", "test_round_three_slips"]
R3_CHARGE = whole(R3_ALWAYS + ["test_charge_map", "test_voltage_logs_cli", "test_battery_cli", "test_battery_fit",
                               "test_small_data_cli"])
R3_NOISE = whole(R3_ALWAYS + ["test_reading_noise", "test_diagnose_noise", "test_sensor_fits", "test_sensor_cli",
                              "test_measured_logs", "test_model_loop", "test_diagnose_steps", "test_honest_fits"])
R3_CODEGEN = whole(R3_ALWAYS + ["test_coefficients", "test_model_loop", "test_battery_cli", "test_model_sets",
                                "test_checked_outputs"])
R3_LIKE = whole(R3_ALWAYS + ["test_model_loop", "test_coefficients", "test_checked_outputs", "test_voltage_logs_cli",
                             "test_small_data_cli"])
R3_DIAGNOSE = whole(R3_ALWAYS + ["test_diagnose", "test_diagnose_steps", "test_diagnose_noise", "test_honest_fits",
                                 "test_independent_checks", "test_model_loop", "test_long_logs"])
R3_FIT = whole(R3_ALWAYS + ["test_report", "test_report_files", "test_measured_logs", "test_sensor_fits",
                            "test_independent_checks", "test_honest_fits", "test_nist", "test_linear_start", "test_sensor_cli",
                            "test_diagnose_steps", "test_sensor_models"])
R3_CAP = whole(R3_ALWAYS + ["test_sensor_fits", "test_measured_logs", "test_independent_checks", "test_honest_fits",
                            "test_sensor_cli", "test_diagnose_steps", "test_model_loop"])
R3_HINTS = whole(R3_ALWAYS + ["test_log_reader", "test_cli_grammar", "test_honest_fits", "test_sensor_cli",
                              "test_diagnose_steps"])
R3_MODEL = whole(R3_ALWAYS + ["test_coefficients", "test_model_sets", "test_model_loop", "test_log_reader",
                              "test_checked_outputs"])
# The ARGoS plug-in and its tests (every one but the battery's, which the sensors' noise does not touch).
R3_ARGOS = (["epuck2-fit", "epuck2_argos_calibrated", "epuck2_argos_protocols", "argos_hidden_log", "argos_reset_check",
             "test_argos_calibrated_drive"],
            ("whole", (), ("argos_noise_", "argos_roundtrip_proximity", "argos_roundtrip_ground", "argos_roundtrip_light",
                           "argos_roundtrip_drive", "argos_roundtrip_camera", "argos_roundtrip_default_", "argos_calibrated_",
                           "argos_hostile_files", "argos_closed_loop_proximity_", "argos_closed_loop_ground_",
                           "argos_closed_loop_light_", "argos_closed_loop_camera_", "argos_closed_loop_protocol_",
                           "argos_replay_like")))
DR = "lib/diagnose/src/reading_noise.cpp"
KG = "lib/diagnose/src/kind_ground.cpp"
PL = "lib/calibrate/src/plausibility.cpp"
AS = "argos/src/calibrated_sensors.cpp"

# Round 4 of the fresh slips (bench/fresh-slips.md, branch fresh-slips-4), planted without reading
# the tests; each group is every test of the programs that touch the area, as in round 3.
R4_ALWAYS = R3_ALWAYS + ["test_round_four_slips"]


def with_round_four(group):
    """A round-3 whole group with tests/test_round_four_slips.cpp's tests too."""
    return whole(list(group[1][1]) + ["test_round_four_slips"], group[1][2])


R4_FIT = whole(R4_ALWAYS + ["test_readings", "test_sensor_fits", "test_sensor_models", "test_independent_checks",
                            "test_honest_fits", "test_measured_logs", "test_report", "test_report_files", "test_sensor_cli",
                            "test_diagnose_steps", "test_model_loop"])
R4_REPORT = whole(R4_ALWAYS + ["test_report", "test_report_files", "test_report_rooms", "test_report_wording", "test_sensor_cli",
                               "test_honest_fits", "test_measured_logs", "test_sensor_fits", "test_coefficients", "test_docs"])
R4_DREPORT = whole(R4_ALWAYS + ["test_diagnose", "test_diagnose_steps", "test_diagnose_noise", "test_report_wording",
                                "test_report_rooms", "test_model_loop", "test_honest_fits", "test_long_logs"])
R4_FACTS = whole(R4_ALWAYS + ["test_coefficients", "test_model_sets", "test_model_loop", "test_log_reader", "test_checked_outputs",
                              "test_report_wording", "test_sensor_cli", "test_honest_fits", "test_diagnose_steps"])
R4_NOISE = whole(R4_ALWAYS + ["test_reading_noise", "test_diagnose_noise", "test_sensor_fits", "test_sensor_cli",
                              "test_measured_logs", "test_model_loop", "test_diagnose_steps", "test_honest_fits", "test_report",
                              "test_report_files", "test_coefficients", "test_model_formulas"])
R4_TOF_CODES = whole(R4_ALWAYS + ["test_diagnose", "test_diagnose_steps", "test_diagnose_noise", "test_honest_fits",
                                  "test_independent_checks", "test_model_loop", "test_long_logs", "test_sensor_fits",
                                  "test_measured_logs"])
R4_LOGS = whole(R4_ALWAYS + ["test_log_reader", "test_cli_grammar", "test_honest_fits", "test_sensor_cli", "test_diagnose_steps",
                             "test_safe_runs", "test_checked_outputs", "test_small_data_cli"])
R4_LIKE = whole(R4_ALWAYS + ["test_model_loop", "test_coefficients", "test_checked_outputs", "test_voltage_logs_cli",
                             "test_small_data_cli", "test_safe_runs"])
R4_PLOT = whole(R4_ALWAYS + ["test_figures", "test_sensor_cli", "test_battery_cli", "test_docs"])
R4_ARGOS = (R3_ARGOS[0], ("whole", (), R3_ARGOS[1][2] + ("argos_incidence_shapes",)))

# Round 5 of the fresh slips (bench/fresh-slips.md, branch fresh-slips-5), planted without reading
# the tests; each group is every test of the programs that touch the area (round 4's groups, which
# already hold round 4's tests), as in rounds 3 and 4.
R5_FACTS = whole(list(R4_FACTS[1][1]) + list(R4_REPORT[1][1]))


def with_round_five(group):
    """A whole group with tests/test_round_five_slips.cpp's tests too (written after the run
    before them; an ARGoS group, which names no test program, is left as it is)."""
    if not group[1][1]:
        return group
    return whole(list(group[1][1]) + ["test_round_five_slips"], group[1][2])

# Round 6 (bench/fresh-slips.md, "Classes of survivors", branch slip-classes): slips of each class of
# rounds 2-5's survivors, planted in places no round had slipped -- by someone who HAD read the
# earlier rounds' tests (not a fresh round). Each group is every test of the programs that touch
# the area (the earlier rounds' groups, with test_strict_files and test_kind_facts, which read model
# files and kind_facts too) and tests/test_slip_classes.cpp, the tests that close the classes. (The
# run "before" them, on main's tests, had C6_TESTS = [], commit adbd788.)
# C8_TESTS: tests/test_classes_eight.cpp (session 8, "Classes closed (session 8)"), in the c6 and r7
# groups alike, so that the next run of either includes them.
C8_TESTS = ["test_classes_eight"]
C6_TESTS = ["test_slip_classes"] + C8_TESTS


def c6(group, more=()):
    return whole(list(group[1][1]) + list(more) + C6_TESTS, group[1][2])


C6_REPORT = c6(with_round_five(R4_REPORT))
C6_DREPORT = c6(with_round_five(R4_DREPORT))
C6_CODEGEN = c6(with_round_five(with_round_four(R3_CODEGEN)), ["test_strict_files"])
C6_LIKE = c6(with_round_five(R4_LIKE))
C6_MODEL = c6(with_round_five(R5_FACTS), ["test_strict_files", "test_kind_facts"])
C6_LOGS = c6(with_round_five(R4_LOGS), ["test_kind_facts", "test_long_logs"])
C6_FIT = c6(with_round_five(R4_FIT))

# Round 7 of the fresh slips (bench/fresh-slips.md, branch fresh-slips-7), planted without reading
# the tests: each group is every test of the programs that touch the area -- the earlier rounds'
# groups for it (with round 5's and the classes' tests) and the programs of the code changed since
# (the one engine, the light's per-sensor gammas, the file owner, the third distortion term).
# R7_TESTS: tests/test_round_seven_slips.cpp, written after the run before them (that run had
# R7_TESTS = [], commit ff3f0c0).
R7_TESTS = ["test_round_seven_slips"] + C8_TESTS


def r7(groups, more=(), extra=()):
    programs = [p for g in groups for p in g[1][1]]
    return whole(programs + list(more) + R7_TESTS, tuple(e for g in groups for e in g[1][2]) + tuple(extra))


R7_FIT = r7([C6_FIT], ["test_one_engine", "test_linear_start", "test_nist", "test_charge_map", "test_battery_fit",
                       "test_battery_fast_paths", "test_diagnose", "test_diagnose_noise", "test_light_gammas"])
# lib/fit's dual numbers: the CTest that compares them with Ceres' jet.h is its own program.
R7_JET = (R7_FIT[0] + ["test_fit_jet_matches_ceres"], ("whole", R7_FIT[1][1], R7_FIT[1][2] + ("fit_jet_matches_ceres",)))
R7_COEFF = r7([C6_CODEGEN, C6_MODEL], ["test_file_owner", "test_light_gammas", "test_distortion_k3", "test_battery_fit",
                                      "test_battery_fast_paths", "test_sensor_cli", "test_voltage_logs_cli"])
R7_MODELS = r7([C6_LIKE, C6_MODEL, C6_DREPORT], ["test_light_gammas", "test_distortion_k3", "test_file_owner", "test_sensor_models",
                                                "test_model_formulas", "test_virtual_robot_sensors", "test_diagnose"])
R7_CALIB = r7([C6_REPORT], ["test_battery_cli", "test_battery_fit", "test_battery_fast_paths", "test_file_owner",
                           "test_voltage_logs_cli", "test_small_data_cli", "test_sensor_fits", "test_light_gammas"])
R7_DIAGNOSE = r7([C6_DREPORT, with_round_five(with_round_four(R3_DIAGNOSE))], ["test_light_gammas"])
R7_LOGS = r7([C6_LOGS], ["test_battery_cli", "test_voltage_logs_cli", "test_measured_logs", "test_long_logs"])
R7_APPS = r7([C6_LOGS, C6_DREPORT], ["test_safe_cli", "test_battery_cli", "test_voltage_logs_cli", "test_model_loop"], ("fuzz_smoke",))
R7_ARGOS = with_round_five(R4_ARGOS)

# Round 8 of the fresh slips (bench/fresh-slips.md, branch fresh-slips-8), planted without reading
# the tests: each group is every test of the programs that touch the area -- round 7's groups for
# it (which hold the earlier rounds' and the classes' groups) and, for the charge map, the reading
# noise and the unit hints, round 3's and 4's groups of those areas.
# R8_TESTS: tests/test_round_eight_slips.cpp, written after the run before them started (that run had
# R8_TESTS = R7_TESTS, commit 50379fa).
# tests/test_classes_nine.cpp: round 8's survivor classes closed elsewhere (written before round 9).
R8_TESTS = R7_TESTS + ["test_round_eight_slips", "test_classes_nine"]


def r8(groups, more=(), extra=()):
    programs = [p for g in groups for p in g[1][1]]
    return whole(programs + list(more) + R8_TESTS, tuple(e for g in groups for e in g[1][2]) + tuple(extra))


R8_FIT = r8([R7_FIT])
R8_JET = (R8_FIT[0] + ["test_fit_jet_matches_ceres"], ("whole", R8_FIT[1][1], R8_FIT[1][2] + ("fit_jet_matches_ceres",)))
R8_COEFF = r8([R7_COEFF])
R8_MODELS = r8([R7_MODELS])
R8_FACTS = r8([R7_LOGS, R7_MODELS])
R8_CALIB = r8([R7_CALIB, R3_CHARGE, R4_NOISE])
R8_DIAGNOSE = r8([R7_DIAGNOSE])
R8_HINTS = r8([R7_LOGS, R3_HINTS])
R8_APPS = r8([R7_APPS, C6_LIKE])
R8_ARGOS = R7_ARGOS

# Round 9 of the fresh slips (bench/fresh-slips.md, branch fresh-slips-9), planted without reading
# the tests: each group is every test of the programs that touch the area -- round 8's groups for it
# (which hold the earlier rounds' and the classes' groups), with their build targets merged so that
# a group that holds the ARGoS tests also builds the plug-in. R9_TESTS: tests/test_round_nine_slips.cpp,
# written while the run before them went on (that run, from fd79662, had R9_TESTS = R8_TESTS, which
# holds main's test_classes_nine, merged before it).
# tests/test_classes_ten.cpp and test_kind_facts (its cells that are not numbers): round 9's survivor
# classes closed elsewhere (written before round 10, in every r9 group and so in round 10's).
R9_TESTS = R8_TESTS + ["test_round_nine_slips", "test_classes_ten", "test_kind_facts"]


def r9(groups, more=(), extra=()):
    targets = {t for g in groups for t in g[0]} | set(more) | set(R9_TESTS) | {"epuck2-fit"}
    programs = {p for g in groups for p in g[1][1]} | set(more) | set(R9_TESTS)
    extras = tuple(dict.fromkeys(e for g in groups for e in g[1][2])) + tuple(extra)
    return (sorted(targets), ("whole", tuple(sorted(programs)), extras))


R9_FACTS = r9([R8_FACTS, R8_CALIB])
R9_MODELS = r9([R8_MODELS])
R9_CAMERA = r9([R8_MODELS, R8_ARGOS])
R9_FIT = r9([R8_FIT, R8_CALIB])
R9_COEFF = r9([R8_COEFF, R8_ARGOS])
R9_CALIB = r9([R8_CALIB])
R9_DIAGNOSE = r9([R8_DIAGNOSE])
R9_LOGS = r9([R8_FACTS, R8_HINTS, R8_APPS])
R9_APPS = r9([R8_APPS, R3_CHARGE], ["test_battery_models", "test_battery_fast_paths"])
R9_ARGOS = r9([R8_ARGOS])

# Round 10 of the fresh slips (bench/fresh-slips.md, branch fresh-slips-10), planted without reading
# the tests: each group is every test of the programs that touch the area -- round 8's groups for it,
# as in round 9, with the ARGoS tests for argos/src and for the model headers the plug-in includes.
# `targets` are build targets that are no test program (ctest runs them through a script): the
# battery's bit-exactness helper, for the slips the ARGoS battery tests compare against. The ARGoS
# drive slips also run the drive's closed loops, and the discharge and battery-table slips the ARGoS
# battery tests (R3_ARGOS leaves both out). R10_TESTS: the programs added for round 10 (none yet).
R10_TESTS = R9_TESTS + [
    "test_round_ten_slips",  # written after round 10's run began (session 12)
    "test_figure_data", "test_generator_truth",  # session 13, before round 11's GO (03:19 UTC)
    "test_probed_areas", "test_text_and_json",  # session 13, after round 11's GO
    "test_round_eleven_slips",
]
R10_ARGOS_BATTERY = ("argos_battery_", "argos_closed_loop_battery_")


def r10(groups, more=(), extra=(), targets=()):
    built = {t for g in groups for t in g[0]} | set(more) | set(R10_TESTS) | set(targets) | {"epuck2-fit"}
    programs = {p for g in groups for p in g[1][1]} | set(more) | set(R10_TESTS)
    extras = tuple(dict.fromkeys(tuple(e for g in groups for e in g[1][2]) + tuple(extra)))
    return (sorted(built), ("whole", tuple(sorted(programs)), extras))


R10_MODELS = r10([R8_MODELS, R8_ARGOS])
R10_DISCHARGE = r10([R9_APPS, R8_CALIB], extra=R10_ARGOS_BATTERY, targets=R3_ARGOS[0] + ["argos_plugin_battery_json"])
R10_ARGOS = r10([R8_ARGOS], extra=("argos_closed_loop_drive_",))
R10_FIT = r10([R8_FIT, R8_CALIB, R8_DIAGNOSE])
R10_COEFF = r10([R8_COEFF, R8_ARGOS], extra=R10_ARGOS_BATTERY, targets=["argos_plugin_battery_json"])
R10_CALIB = r10([R8_CALIB])
R10_LOGS = r10([R8_FACTS, R8_HINTS, R8_APPS])
R10_DIAGNOSE = r10([R8_DIAGNOSE], ["test_battery_cli", "test_battery_fit", "test_battery_models"])
R10_APPS = r10([R8_APPS, R3_CHARGE], ["test_battery_models", "test_battery_fast_paths"])

# Round 11 of the fresh slips (bench/fresh-slips.md, branch fresh-slips-11), planted without reading
# the tests: each group is every test of the programs that touch the area -- round 8's groups for it,
# as in rounds 9 and 10, with the ARGoS tests for argos/src and for the drive model the plug-in's
# actuator runs (and the drive's closed loops), the ARGoS battery tests for the calibrated battery
# and the battery tables. R11_TESTS: the programs added for round 11 (none yet: R10_TESTS, which
# holds session 13's test_figure_data).
R11_TESTS = R10_TESTS


def r11(groups, more=(), extra=(), targets=()):
    built = {t for g in groups for t in g[0]} | set(more) | set(R11_TESTS) | set(targets) | {"epuck2-fit"}
    programs = {p for g in groups for p in g[1][1]} | set(more) | set(R11_TESTS)
    extras = tuple(dict.fromkeys(tuple(e for g in groups for e in g[1][2]) + tuple(extra)))
    return (sorted(built), ("whole", tuple(sorted(programs)), extras))


# saturation.hpp: the fits' and the diagnosis's expected clamped reading (the plug-in does not include it).
R11_SATURATION = r11([R8_MODELS, R8_FIT, R8_CALIB, R8_DIAGNOSE])
# drive.hpp: simulate --like, the drive's calibration and diagnosis, and the plug-in's calibrated actuator.
R11_DRIVE_MODEL = r11([R8_MODELS, R8_CALIB, R8_DIAGNOSE, R8_ARGOS], extra=("argos_closed_loop_drive_",))
R11_ARGOS = r11([R8_ARGOS], extra=("argos_closed_loop_drive_",))
R11_ARGOS_BATTERY = r11([R8_COEFF, R8_ARGOS], extra=R10_ARGOS_BATTERY, targets=["argos_plugin_battery_json"])
R11_FIT = r11([R8_FIT, R8_CALIB, R8_DIAGNOSE])
R11_COEFF = r11([R8_COEFF, R8_ARGOS], extra=R10_ARGOS_BATTERY, targets=["argos_plugin_battery_json"])
R11_CALIB = r11([R8_CALIB])
R11_DIAGNOSE = r11([R8_DIAGNOSE], ["test_battery_cli", "test_battery_fit", "test_battery_models"])
R11_LOGS = r11([R8_FACTS, R8_HINTS, R8_APPS])
# drive_columns.hpp: the drive's calibration and diagnosis read a drive log through it.
R11_DRIVE_COLUMNS = r11([R8_FACTS, R8_HINTS, R8_APPS, R8_CALIB, R8_DIAGNOSE])
R11_APPS = r11([R8_APPS, R3_CHARGE], ["test_battery_models", "test_battery_fast_paths", "test_nist"])
R11_PLOT = r11([R8_APPS, R3_CHARGE], ["test_figures", "test_battery_models", "test_battery_fast_paths"])

# Round 12 of the fresh slips (bench/fresh-slips.md, branch fresh-slips-12), planted without reading
# the tests: each group is every test of the programs that touch the area -- round 8's groups for it,
# as in rounds 9-11, with the ARGoS tests for argos/src and for the model headers the plug-in
# includes, the generators' programs for lib/virtual_robot (`generate` and the shipped logs), the
# battery programs for the battery's tables, reports and figures. R12_TESTS: the programs added for
# round 12, written after its run (session 14): the CLI corners (round 12's survivors), the
# voltage-only table5 line, the charge-map reader's refusals, the geometry and LED facts.
R12_TESTS = R11_TESTS + ["test_cli_corners", "test_voltage_logs_cli", "test_charge_map", "test_sensor_models",
             "test_round_twelve_stability"]
R12_GENERATORS = ["test_virtual_robot_sensors", "test_virtual_robot_battery", "test_battery_models", "test_battery_fast_paths"]
R12_BATTERY = ["test_battery_models", "test_battery_fast_paths", "test_battery_fit", "test_battery_cli", "test_virtual_robot_battery"]


def r12(groups, more=(), extra=(), targets=()):
    built = {t for g in groups for t in g[0]} | set(more) | set(R12_TESTS) | set(targets) | {"epuck2-fit"}
    programs = {p for g in groups for p in g[1][1]} | set(more) | set(R12_TESTS)
    extras = tuple(dict.fromkeys(tuple(e for g in groups for e in g[1][2]) + tuple(extra)))
    return (sorted(built), ("whole", tuple(sorted(programs)), extras))


# plugin_battery_tables.hpp: every reader of the plug-in's tables (the battery's calibration, reports,
# figures, diagnosis, generator, coefficient files, simulate) and the ARGoS battery tests.
R12_PLUGIN_TABLES = r12([R8_MODELS, R8_COEFF, R8_CALIB, R8_DIAGNOSE, R8_APPS, R8_ARGOS, R3_CHARGE],
                        R12_BATTERY + ["test_figures"], extra=R10_ARGOS_BATTERY, targets=["argos_plugin_battery_json"])
# noise.hpp: simulate --like's Gaussian noise (StandardNormal) and the plug-in's sensors (sensors.hpp).
R12_NOISE = r12([R8_MODELS, R8_APPS, R8_ARGOS])
R12_ARGOS = r12([R8_ARGOS], extra=("argos_closed_loop_drive_",))
# lib/virtual_robot: `generate` and the shipped logs' generators.
R12_GENERATE = r12([R8_MODELS, R8_APPS, R3_CHARGE], R12_GENERATORS)
R12_PLOT = r12([R8_APPS, R3_CHARGE], ["test_figures"] + R12_BATTERY)
R12_DIAGNOSIS_FIGURE = r12([R8_APPS, R8_DIAGNOSE], ["test_figures"])
R12_APPS = r12([R8_APPS, R3_CHARGE, R8_CALIB], R12_BATTERY + ["test_figures"])
# csv_writer.cpp: every log and number the program writes (the generators' logs included).
R12_LOGS = r12([R8_FACTS, R8_HINTS, R8_APPS], R12_GENERATORS)
R12_CALIB = r12([R8_CALIB], R12_BATTERY)
R12_FIT = r12([R8_FIT, R8_CALIB, R8_DIAGNOSE])
R12_COEFF = r12([R8_COEFF, R8_ARGOS], R12_BATTERY, extra=R10_ARGOS_BATTERY, targets=["argos_plugin_battery_json"])
R12_DIAGNOSE = r12([R8_DIAGNOSE], ["test_battery_cli", "test_battery_fit", "test_battery_models"])

# Round 13 of the fresh slips (bench/fresh-slips.md, branch fresh-slips-13), planted without reading
# the tests: each group is every test of the programs that touch the area -- round 8's groups for it,
# as in rounds 9-12, with the ARGoS tests for argos/src and for the model headers the plug-in
# includes, the battery programs for the battery's files, calibration and the ARGoS battery, the
# generators' programs for lib/virtual_robot. R13_TESTS: the programs added for round 13, written
# by the lead during its run (after its GO, so not in the run that scored it): test_round_thirteen
# (its three survivors, its two stability-only kills and the behaviours its other slips change).
# argos_calibrated_ground_rail is in the ARGoS groups by its prefix. test_metamorphic (written
# before round 14's GO: the same readings in another order or split into two files calibrate the
# same; the diagnosis's counts against the raw logs) runs in every later group through this list.
R13_TESTS = R12_TESTS + ["test_round_thirteen", "test_metamorphic"]


def r13(groups, more=(), extra=(), targets=()):
    built = {t for g in groups for t in g[0]} | set(more) | set(R13_TESTS) | set(targets) | {"epuck2-fit"}
    programs = {p for g in groups for p in g[1][1]} | set(more) | set(R13_TESTS)
    extras = tuple(dict.fromkeys(tuple(e for g in groups for e in g[1][2]) + tuple(extra)))
    return (sorted(built), ("whole", tuple(sorted(programs)), extras))


# camera.hpp (camera_image_holds: simulate --like and the plug-in's camera) and light.hpp (the
# several-lights mean: the plug-in's light sensor): the models', apps' and ARGoS groups.
R13_MODELS = r13([R8_MODELS, R8_APPS, R8_ARGOS])
R13_ARGOS = r13([R8_ARGOS], extra=("argos_closed_loop_drive_",))
# the calibrated battery, the battery tables' reader, the model-file reader: the coefficients'
# and ARGoS groups with the ARGoS battery tests and the battery programs.
R13_COEFF = r13([R8_COEFF, R8_ARGOS], R12_BATTERY, extra=R10_ARGOS_BATTERY, targets=["argos_plugin_battery_json"])
# charge_map.hpp, battery_fit.cpp: the calibration's and apps' groups (battery, table5, voltage logs).
R13_BATTERY_CALIB = r13([R8_CALIB, R8_APPS], R12_BATTERY + ["test_figures"])
# reading_noise.hpp: every calibration's noise section and text, the coefficient files.
R13_CALIB = r13([R8_CALIB, R8_APPS, R8_COEFF])
R13_APPS = r13([R8_APPS, R3_CHARGE, R8_CALIB], R12_BATTERY + ["test_figures"])
R13_FIT = r13([R8_FIT, R8_CALIB, R8_DIAGNOSE])
# json_location.cpp: where every coefficient-file error is placed (the readers, the CLI, ARGoS).
R13_LOGS = r13([R8_COEFF, R8_FACTS, R8_APPS, R8_ARGOS])
R13_DIAGNOSE = r13([R8_DIAGNOSE, R8_APPS], ["test_battery_cli", "test_battery_fit", "test_battery_models"])
# lib/virtual_robot: `generate` and the shipped logs' generators.
R13_GENERATE = r13([R8_MODELS, R8_APPS, R3_CHARGE], R12_GENERATORS)

# Round 14 of the fresh slips (bench/fresh-slips.md, branch fresh-slips-14), planted without reading
# the tests: each group is every test of the programs that touch the area -- round 8's groups for it,
# as in rounds 9-13, with the ARGoS tests for argos/src and for the model headers and coefficient-file
# code the plug-in runs (the drive's closed loops for the drive), the battery programs for the
# battery's calibration, the generators' programs for the virtual battery's fit. R14_TESTS: the
# programs of rounds up to 13 and test_round_fourteen, written by the lead during round 14's run
# (after its GO, so not in the run that scored it); the ToF delay line's case is in
# test_argos_calibrated_drive, which the ARGoS groups build. test_like_checks (every fit's own
# lack-of-fit check, each camera column's screening) was written after round 14, before round 15's GO.
R14_TESTS = R13_TESTS + ["test_round_fourteen", "test_like_checks"]


def r14(groups, more=(), extra=(), targets=()):
    built = {t for g in groups for t in g[0]} | set(more) | set(R14_TESTS) | set(targets) | {"epuck2-fit"}
    programs = {p for g in groups for p in g[1][1]} | set(more) | set(R14_TESTS)
    extras = tuple(dict.fromkeys(tuple(e for g in groups for e in g[1][2]) + tuple(extra)))
    return (sorted(built), ("whole", tuple(sorted(programs)), extras))


# drive.hpp (drive_advance's one-wheel path): the drive's calibration, its diagnosis, simulate --like
# and the plug-in's drive, encoders and ToF.
R14_DRIVE_MODEL = r14([R8_MODELS, R8_APPS, R8_DIAGNOSE, R8_ARGOS], extra=("argos_closed_loop_drive_",))
# geometry.hpp's rad_to_deg: the camera's calibration, reports, model files, diagnosis and the plug-in.
R14_GEOMETRY = r14([R8_MODELS, R8_APPS, R8_CALIB, R8_COEFF, R8_DIAGNOSE, R8_ARGOS])
# calibrated_drive.hpp (the ToF's delay line, the encoders' step register): the ARGoS groups.
R14_ARGOS = r14([R8_ARGOS], extra=("argos_closed_loop_drive_",))
# lib/fit (the wild replicates, the reported correlations): the fits', calibration's and diagnosis's groups.
R14_FIT = r14([R8_FIT, R8_CALIB, R8_DIAGNOSE])
# lib/fit problem.hpp's autodiff of several blocks: the engine's groups and the virtual battery (its
# calibration to the published curves is the one fit of several blocks), `generate`, the shipped logs.
R14_AUTODIFF = r14([R8_FIT, R8_APPS, R3_CHARGE], R12_GENERATORS + ["test_figures"])
# the calibration (the drive's lagged travel, the quantisation floor, the camera's Table 4): the
# calibration's, apps' and coefficients' groups.
R14_CALIB = r14([R8_CALIB, R8_APPS, R8_COEFF])
# battery.hpp's rejection: the calibration's and apps' groups with the battery programs and the figures.
R14_BATTERY_CALIB = r14([R8_CALIB, R8_APPS], R12_BATTERY + ["test_figures"])
# the diagnosis's kinds and noise warnings: its group, the apps' and the battery programs.
R14_DIAGNOSE = r14([R8_DIAGNOSE, R8_APPS], ["test_battery_cli", "test_battery_fit", "test_battery_models"])
# extended_model.cpp: the diagnosis's model files, which the coefficient readers and the plug-in read.
R14_EXTENDED = r14([R8_DIAGNOSE, R8_APPS, R8_COEFF, R8_ARGOS], ["test_battery_cli", "test_battery_fit", "test_battery_models"])
# model_sets.cpp (the plug-in's robot sets): the coefficients' and ARGoS groups with the ARGoS
# battery tests and the battery programs.
R14_COEFF = r14([R8_COEFF, R8_ARGOS], R12_BATTERY, extra=R10_ARGOS_BATTERY, targets=["argos_plugin_battery_json"])
# output.cpp (every file the program writes): the facts', hints', apps' and coefficients' groups,
# the generators.
R14_LOGS = r14([R8_FACTS, R8_HINTS, R8_APPS, R8_COEFF], R12_GENERATORS + ["test_figures"])
R14_APPS = r14([R8_APPS, R3_CHARGE, R8_CALIB], R12_BATTERY + ["test_figures"])

# Round 15 of the fresh slips (bench/fresh-slips.md, branch fresh-slips-15), planted without reading
# the tests: each group is every test of the programs that touch the area -- round 8's groups for it,
# as in rounds 9-14, with the ARGoS tests for argos/src and for the model headers and coefficient-file
# code the plug-in runs (the drive's closed loops for the drive), the battery programs for the
# battery's reports. R15_TESTS: the programs of rounds up to 14 and test_round_fifteen, written by
# the lead during round 15's run (after its GO, so not in the run that scored it).
R15_TESTS = R14_TESTS + ["test_round_fifteen"]


def r15(groups, more=(), extra=(), targets=()):
    built = {t for g in groups for t in g[0]} | set(more) | set(R15_TESTS) | set(targets) | {"epuck2-fit"}
    programs = {p for g in groups for p in g[1][1]} | set(more) | set(R15_TESTS)
    extras = tuple(dict.fromkeys(tuple(e for g in groups for e in g[1][2]) + tuple(extra)))
    return (sorted(built), ("whole", tuple(sorted(programs)), extras))


# lib/models encoders.hpp (unwrap_steps: the drive's calibration and diagnosis) and proximity.hpp
# (proximity_mean_raw: simulate --like, the diagnosis, the plug-in's proximity): every group that
# reads a model, the ARGoS tests and the drive's closed loops.
R15_MODELS = r15([R8_MODELS, R8_APPS, R8_CALIB, R8_COEFF, R8_DIAGNOSE, R8_ARGOS], extra=("argos_closed_loop_drive_",))
# calibrated_sensors.cpp (the proximity's surface normal on a cylinder, the ground's grey): the ARGoS groups.
R15_ARGOS = r15([R8_ARGOS], extra=("argos_closed_loop_drive_",))
# lib/fit (the wild replicates' groups and their limit): the fits',
# calibration's and diagnosis's groups.
R15_FIT = r15([R8_FIT, R8_CALIB, R8_DIAGNOSE])
# lib/coefficients (robot_map's patterns, the proximity's means curve): the coefficients' and ARGoS
# groups with the ARGoS battery tests and the battery programs.
R15_COEFF = r15([R8_COEFF, R8_ARGOS], R12_BATTERY, extra=R10_ARGOS_BATTERY, targets=["argos_plugin_battery_json"])
# the calibration (proximity's range, the units check, the camera's model, the noise text): the calibration's, apps' and coefficients' groups.
R15_CALIB = r15([R8_CALIB, R8_APPS, R8_COEFF])
# battery_report.cpp and published.hpp (Table 5's paper rows): the calibration's and apps' groups with the battery programs and the figures.
R15_BATTERY_CALIB = r15([R8_CALIB, R8_APPS], R12_BATTERY + ["test_figures"])
# kind_common.hpp (the effects' parameter names, which the diagnosis's model files carry to the
# coefficient readers and the plug-in) and screening.hpp (the ToF dropouts): the diagnosis's group,
# the apps', coefficients' and ARGoS groups and the battery programs.
R15_DIAGNOSE = r15([R8_DIAGNOSE, R8_APPS, R8_COEFF, R8_ARGOS], ["test_battery_cli", "test_battery_fit", "test_battery_models"])
# json_location.cpp: where every coefficient-file error is placed (the readers, the CLI, ARGoS).
R15_LOGS = r15([R8_COEFF, R8_FACTS, R8_APPS, R8_ARGOS])
# apps/ (sensor_support.hpp's -o -, camera's --help, codegen's inputs): the apps', charge map's,
# calibration's and coefficients' groups with the battery programs and the figures.
R15_APPS = r15([R8_APPS, R3_CHARGE, R8_CALIB, R8_COEFF], R12_BATTERY + ["test_figures"])

# Round 16 of the fresh slips (bench/fresh-slips.md, branch fresh-slips-16), planted without reading
# the tests, mostly in files no earlier round slipped: each group is every test of the programs that
# touch the area (round 8's groups for it, as in rounds 9-15), the ARGoS groups for argos/src and for
# the coefficient-file code the plug-in reads. R16_TESTS: the programs of rounds up to 15.
# test_round_sixteen: written by the lead during round 16's run (after its GO, not in the run that scored it).
# test_refusal_reasons (each refusal's own reason, on inputs only that rule refuses): before round 17's GO.
R16_TESTS = R15_TESTS + ["test_round_sixteen", "test_refusal_reasons"]


def r16(groups, more=(), extra=(), targets=()):
    built = {t for g in groups for t in g[0]} | set(more) | set(R16_TESTS) | set(targets) | {"epuck2-fit"}
    programs = {p for g in groups for p in g[1][1]} | set(more) | set(R16_TESTS)
    extras = tuple(dict.fromkeys(tuple(e for g in groups for e in g[1][2]) + tuple(extra)))
    return (sorted(built), ("whole", tuple(sorted(programs)), extras))


# engine.cpp (the diagnosis's common covariates: which log a row is from): the diagnosis's,
# apps' and coefficients' groups and the battery programs (the battery's diagnosis).
R16_DIAGNOSE = r16([R8_DIAGNOSE, R8_APPS, R8_COEFF], ["test_battery_cli", "test_battery_fit", "test_battery_models"])
# report_json.hpp (each sensor's noise in the model) and drive_report.cpp (the firmware cap's BICs):
# the calibration's, apps' and coefficients' groups.
R16_CALIB = r16([R8_CALIB, R8_APPS, R8_COEFF])
# fit_curve.cpp (the bounds given to the solver): the fits' (with the Jet check), calibration's and
# diagnosis's groups and the battery programs.
R16_FIT = r16([R8_JET, R8_CALIB, R8_DIAGNOSE], R12_BATTERY)
# model_sets.cpp (the coefficient files' cache): the coefficients' and ARGoS groups with the ARGoS
# battery tests and the battery programs.
R16_COEFF = r16([R8_COEFF, R8_ARGOS], R12_BATTERY, extra=R10_ARGOS_BATTERY, targets=["argos_plugin_battery_json"])
# argos_noise.hpp (the Gaussian noise's level): the ARGoS groups.
R16_ARGOS = r16([R8_ARGOS], extra=("argos_closed_loop_drive_",))
# csv_writer.cpp (LogWriter's refusal of a non-finite value) and output.cpp (the in-place target's
# check): the facts', hints', apps' and coefficients' groups, the generators and the figures.
R16_LOGS = r16([R8_FACTS, R8_HINTS, R8_APPS, R8_COEFF], R12_GENERATORS + ["test_figures"])
# apps/ (nist's order, the "did you mean" rule): the apps', charge map's, calibration's and
# coefficients' groups with the battery programs, the figures and the NIST program.
R16_APPS = r16([R8_APPS, R3_CHARGE, R8_CALIB, R8_COEFF], R12_BATTERY + ["test_figures", "test_nist"])

# Round 17 of the fresh slips (bench/fresh-slips.md, branch fresh-slips-17), planted without reading
# the tests, in functions and branches no earlier round visited (and the few unvisited files with
# behaviour: lib/fit parameter.hpp): each group is every test of the programs that touch the area
# (round 8's groups for it, as in rounds 9-16), the ARGoS groups for argos/src and for the model
# header and coefficient-file code the plug-in reads. R17_TESTS: the programs of rounds up to 16.
R17_TESTS = list(R16_TESTS) + ["test_round_seventeen",  # written during round 17's run (after its GO, not in the run that scored it)
                                 "test_branch_sides",  # session 19, before round 18's GO: both sides of branches a coverage run showed taken one way
                                 "test_time_origin"]  # session 19, during round 18's run: a log's clock moved


def r17(groups, more=(), extra=(), targets=()):
    built = {t for g in groups for t in g[0]} | set(more) | set(R17_TESTS) | set(targets) | {"epuck2-fit"}
    programs = {p for g in groups for p in g[1][1]} | set(more) | set(R17_TESTS)
    extras = tuple(dict.fromkeys(tuple(e for g in groups for e in g[1][2]) + tuple(extra)))
    return (sorted(built), ("whole", tuple(sorted(programs)), extras))


# camera.hpp (aperture_from_horizontal_fov_rad: the camera's report and model files, the virtual
# robot's camera, the plug-in's camera cone): every group that reads a model, the generators, the
# ARGoS tests and the drive's closed loops.
R17_MODELS = r17([R8_MODELS, R8_APPS, R8_CALIB, R8_COEFF, R8_DIAGNOSE, R8_ARGOS], R12_GENERATORS,
                 extra=("argos_closed_loop_drive_",))
# calibrated_sensors.cpp (the camera's search box, the ground sensors' positions): the ARGoS groups.
R17_ARGOS = r17([R8_ARGOS], extra=("argos_closed_loop_drive_",))
# lib/fit (parameter.hpp's free_parameters, problem.cpp's readings_block, fit_curve.hpp's linear
# start): the fits' (with the Jet check), calibration's and diagnosis's groups, the battery
# programs and the NIST program.
R17_FIT = r17([R8_JET, R8_CALIB, R8_DIAGNOSE], R12_BATTERY + ["test_nist"])
# lib/coefficients (add_robot_set's restore, the light's per-sensor numbers, the battery keys'
# "did you mean"): the coefficients' and ARGoS groups with the ARGoS battery tests and the battery programs.
R17_COEFF = r17([R8_COEFF, R8_ARGOS], R12_BATTERY, extra=R10_ARGOS_BATTERY, targets=["argos_plugin_battery_json"])
# the calibration (report_text.cpp's method and noise lines, the proximity's range): the
# calibration's, apps' and coefficients' groups.
R17_CALIB = r17([R8_CALIB, R8_APPS, R8_COEFF])
# the diagnosis (the camera's image_row covariate, the drive's spike screening): the diagnosis's,
# apps' and coefficients' groups and the battery programs.
R17_DIAGNOSE = r17([R8_DIAGNOSE, R8_APPS, R8_COEFF], ["test_battery_cli", "test_battery_fit", "test_battery_models"])
# log.cpp (CRLF lines, escape_control): the facts', hints', apps' and coefficients' groups, the
# generators and the figures.
R17_LOGS = r17([R8_FACTS, R8_HINTS, R8_APPS, R8_COEFF], R12_GENERATORS + ["test_figures"])
# apps/ (simulate --like's unseen rows and metadata, --skip-bad-rows' report): the apps', charge
# map's, calibration's and coefficients' groups with the battery programs, the figures and NIST.
R17_APPS = r17([R8_APPS, R3_CHARGE, R8_CALIB, R8_COEFF], R12_BATTERY + ["test_figures", "test_nist"])

# Round 18 of the fresh slips (bench/fresh-slips.md, branch fresh-slips-18), planted without reading
# the tests, in functions and branches no earlier round visited: each group is every test of the
# programs that touch the area (round 8's groups for it, as in rounds 9-17), the ARGoS groups for
# argos/src and for the model header and coefficient-file code the plug-in reads. R18_TESTS: the
# programs of rounds up to 17.
R18_TESTS = list(R17_TESTS) + ["test_round_eighteen",  # written after round 18's run (not in the run that scored it)
                                 "test_every_refusal",  # session 20, before round 19's GO: each refusal no test quoted
                                 "test_report_lines"]  # session 20, before round 19's GO: the text reports' lines no test quoted


def r18(groups, more=(), extra=(), targets=()):
    built = {t for g in groups for t in g[0]} | set(more) | set(R18_TESTS) | set(targets) | {"epuck2-fit"}
    programs = {p for g in groups for p in g[1][1]} | set(more) | set(R18_TESTS)
    extras = tuple(dict.fromkeys(tuple(e for g in groups for e in g[1][2]) + tuple(extra)))
    return (sorted(built), ("whole", tuple(sorted(programs)), extras))


# saturation.hpp (expected_clamp far above the upper clamp: the fits' and diagnosis's saturated
# readings, the plug-in's): every group that reads a model, the generators, the ARGoS tests and
# the drive's closed loops.
R18_MODELS = r18([R8_MODELS, R8_APPS, R8_CALIB, R8_COEFF, R8_DIAGNOSE, R8_ARGOS], R12_GENERATORS,
                 extra=("argos_closed_loop_drive_",))
# calibrated_drive.cpp (the firmware cap from the file's steps_per_m) and applied_effects.hpp (what
# the light applies): the ARGoS groups with the drive's closed loops.
R18_ARGOS = r18([R8_ARGOS], extra=("argos_closed_loop_drive_",))
# lib/fit (replicates.cpp's group size, readings.cpp's set_noise_sd check, fit_curve.hpp's one-sided
# bounds): the fits' (with the Jet check), calibration's and diagnosis's groups, the
# battery programs and the NIST program.
R18_FIT = r18([R8_JET, R8_CALIB, R8_DIAGNOSE], R12_BATTERY + ["test_nist"])
# lib/coefficients (model_sets.cpp: a robot set's noise section, robot_map's empty id, a model
# path relative to the working folder): the coefficients' and ARGoS groups with the ARGoS battery
# tests and the battery programs.
R18_COEFF = r18([R8_COEFF, R8_ARGOS], R12_BATTERY, extra=R10_ARGOS_BATTERY, targets=["argos_plugin_battery_json"])
# the calibration (camera_report.cpp's aperture std_error_why, light_report.cpp's rails,
# proximity_report.cpp's wild readings shown): the calibration's, apps' and coefficients' groups.
R18_CALIB = r18([R8_CALIB, R8_APPS, R8_COEFF])
# the diagnosis (the light's per-sensor gamma ratios, the extra columns' covariates and their means in
# the extended model): the diagnosis's, apps' and coefficients' groups and the battery programs.
R18_DIAGNOSE = r18([R8_DIAGNOSE, R8_APPS, R8_COEFF], ["test_battery_cli", "test_battery_fit", "test_battery_models"])
# lib/logs (LogWriter's column name in its refusal, which of a row's errors is reported): the facts',
# hints', apps' and coefficients' groups, the generators and the figures.
R18_LOGS = r18([R8_FACTS, R8_HINTS, R8_APPS, R8_COEFF], R12_GENERATORS + ["test_figures"])
# apps/ (generate's relative --out-dir, table5's voltage-only logs, table5's coverage message): the
# apps', charge map's, calibration's and coefficients' groups with the battery programs, the
# figures and NIST.
R18_APPS = r18([R8_APPS, R3_CHARGE, R8_CALIB, R8_COEFF], R12_BATTERY + ["test_figures", "test_nist"])

# Round 19 of the fresh slips (bench/fresh-slips.md, branch fresh-slips-19), planted without reading
# the tests, in functions and branches no earlier round visited: each group is every test of the
# programs that touch the area (round 8's groups for it, as in rounds 9-18), the ARGoS groups for
# argos/src and for the model header and coefficient-file code the plug-in reads. R19_TESTS: the
# programs of rounds up to 18.
R19_TESTS = list(R18_TESTS) + ["test_round_nineteen",  # written during round 19's run (after its GO, not in the run that scored it)
                                 "test_honest_fits",  # session 20: the drive report's cap lines
                                 "test_new_user_probe",  # session 21: a new user's probe's defects
                                 "test_round_twenty",  # round 20's survivors, written during its run (R20_TESTS inherits it)
                                 "test_probe_three",  # session 22: a third new user's probe's defects
                                 "test_round_twenty_one",  # round 21's survivors, written after its run
                                 "test_probe_four",  # session 23: a fourth new user's probe's defects
                                 "test_probe_three_proximity",  # session 23: the third probe's proximity defects
                                 "test_probe_three_drive",  # session 23: the third probe's drive defects
                                 "test_probe_five",  # session 23: a fifth new user's probe's defects
                                 "test_probe_five_battery",  # session 23: a fifth new user's probe's battery defects
                                 "test_pooled_robots",  # session 24: replicates judged within a robot in pooled fits
                                 "test_probe_six",  # session 24: a sixth new user's probe's defects (the lead's share)
                                 "test_probe_six_robots",  # session 24: a sixth new user's probe's several-robots defects
                                 "test_probe_six_battery",  # session 24: the sixth probe's battery defects
                                 ]


def r19(groups, more=(), extra=(), targets=()):
    built = {t for g in groups for t in g[0]} | set(more) | set(R19_TESTS) | set(targets) | {"epuck2-fit"}
    programs = {p for g in groups for p in g[1][1]} | set(more) | set(R19_TESTS)
    extras = tuple(dict.fromkeys(tuple(e for g in groups for e in g[1][2]) + tuple(extra)))
    return (sorted(built), ("whole", tuple(sorted(programs)), extras))


# proximity.hpp (the incidence factor at or beyond 90 degrees: the fits', the diagnosis's, the
# virtual robot's and the plug-in's proximity): every group that reads a model, the generators,
# the ARGoS tests and the drive's closed loops.
R19_MODELS = r19([R8_MODELS, R8_APPS, R8_CALIB, R8_COEFF, R8_DIAGNOSE, R8_ARGOS], R12_GENERATORS,
                 extra=("argos_closed_loop_drive_",))
# calibrated_actuator.cpp (the drive's reset): the ARGoS groups with the drive's closed loops.
R19_ARGOS = r19([R8_ARGOS], extra=("argos_closed_loop_drive_",))
# lib/fit (report.cpp: the information criteria's undefined reason, a value's decimals beside an
# error of tens or more, the units' cubes): the fits' (with the Jet check), calibration's and
# diagnosis's groups, the battery programs and the NIST program.
R19_FIT = r19([R8_JET, R8_CALIB, R8_DIAGNOSE], R12_BATTERY + ["test_nist"])
# lib/coefficients (model_file.cpp: the pooled set read beside a robot's, a zero standard error;
# battery_tables.cpp: a partial file's speeds) and calibrated_battery.cpp (the model's "approx"
# alias: its battery tests, as round 13's calibrated_battery.cpp mutant): the coefficients' and
# ARGoS groups with the ARGoS battery tests and the battery programs.
R19_COEFF = r19([R8_COEFF, R8_ARGOS], R12_BATTERY, extra=R10_ARGOS_BATTERY, targets=["argos_plugin_battery_json"])
# the calibration (battery_report.cpp's lifetime reason and charge conversion, sensor_fit_common.cpp's
# robot index): the calibration's, apps' and coefficients' groups.
R19_CALIB = r19([R8_CALIB, R8_APPS, R8_COEFF])
# the diagnosis (a one-row battery log, the base model's kind in the refusal, a camera base's
# distortion): the diagnosis's, apps' and coefficients' groups and the battery programs.
R19_DIAGNOSE = r19([R8_DIAGNOSE, R8_APPS, R8_COEFF], ["test_battery_cli", "test_battery_fit", "test_battery_models"])
# lib/logs (json_location.cpp's overflowing negative number, log.cpp's last line without a line
# end): the facts', hints', apps' and coefficients' groups, the generators and the figures.
R19_LOGS = r19([R8_FACTS, R8_HINTS, R8_APPS, R8_COEFF], R12_GENERATORS + ["test_figures"])
# apps/ (diagnose's discharge model from a file, the sensors' --accept-misfit, battery's map
# from_file): the apps', charge map's, calibration's and coefficients' groups with the battery
# programs, the figures and NIST.
R19_APPS = r19([R8_APPS, R3_CHARGE, R8_CALIB, R8_COEFF], R12_BATTERY + ["test_figures", "test_nist"])

# Round 20 of the fresh slips (bench/fresh-slips.md, branch fresh-slips-20), planted without reading
# the tests, in functions and branches no earlier round visited: each group is every test of the
# programs that touch the area (round 8's groups for it, as in rounds 9-19), the ARGoS groups for
# argos/src and for the model header and coefficient-file code the plug-in reads. R20_TESTS: the
# programs of rounds up to 19.
R20_TESTS = list(R19_TESTS)


def r20(groups, more=(), extra=(), targets=()):
    built = {t for g in groups for t in g[0]} | set(more) | set(R20_TESTS) | set(targets) | {"epuck2-fit"}
    programs = {p for g in groups for p in g[1][1]} | set(more) | set(R20_TESTS)
    extras = tuple(dict.fromkeys(tuple(e for g in groups for e in g[1][2]) + tuple(extra)))
    return (sorted(built), ("whole", tuple(sorted(programs)), extras))


# saturation.hpp (the sensor's saturation at its low end without a high one: the light fit's and
# the light diagnosis's clamp at 0): every group that reads a model, the generators, the ARGoS tests
# and the drive's closed loops.
R20_MODELS = r20([R8_MODELS, R8_APPS, R8_CALIB, R8_COEFF, R8_DIAGNOSE, R8_ARGOS], R12_GENERATORS,
                 extra=("argos_closed_loop_drive_",))
# calibrated_sensors.cpp (a proximity ray's cosine of incidence on a cylinder's side): the ARGoS
# groups with the drive's closed loops.
R20_ARGOS = r20([R8_ARGOS], extra=("argos_closed_loop_drive_",))
# lib/fit (least_squares.cpp: the reason of a fit with as many residuals as parameters;
# fit_curve.cpp: a lower bound's name; readings.cpp: a channel's reading at its low rail): the
# fits' (with the Jet check), calibration's and diagnosis's groups, the battery programs and the
# NIST program.
R20_FIT = r20([R8_JET, R8_CALIB, R8_DIAGNOSE], R12_BATTERY + ["test_nist"])
# lib/coefficients (battery_tables.cpp: a partial file without speeds; codegen.cpp: the header's
# comment on a calibration's sources; model_sets.cpp: a null noise section) and
# calibrated_battery.cpp (tables="plugin" without a file: its battery tests, as round 13's and 19's
# calibrated_battery.cpp mutants): the coefficients' and ARGoS groups with the ARGoS battery tests
# and the battery programs.
R20_COEFF = r20([R8_COEFF, R8_ARGOS], R12_BATTERY, extra=R10_ARGOS_BATTERY, targets=["argos_plugin_battery_json"])
# the calibration (proximity_fit.cpp's distance at the range, light_fit.cpp's plug-in MSE beside
# readings at 0, camera_fit.cpp's two observations): the calibration's, apps' and coefficients'
# groups.
R20_CALIB = r20([R8_CALIB, R8_APPS, R8_COEFF])
# the diagnosis (kind_proximity.cpp's one tilted angle and its tail's rows at the range,
# reading_noise.cpp's single-channel noise warning): the diagnosis's, apps' and coefficients'
# groups and the battery programs.
R20_DIAGNOSE = r20([R8_DIAGNOSE, R8_APPS, R8_COEFF], ["test_battery_cli", "test_battery_fit", "test_battery_models"])
# lib/logs (output.cpp: /dev/stderr and /proc/self/fd/N as outputs): the facts', hints', apps' and
# coefficients' groups, the generators and the figures.
R20_LOGS = r20([R8_FACTS, R8_HINTS, R8_APPS, R8_COEFF], R12_GENERATORS + ["test_figures"])
# apps/ (simulate --like of a log with one text column, table5's speeds not in 0..15, a ranged
# number option given nan): the apps', charge map's, calibration's and coefficients' groups with the
# battery programs, the figures and NIST.
R20_APPS = r20([R8_APPS, R3_CHARGE, R8_CALIB, R8_COEFF], R12_BATTERY + ["test_figures", "test_nist"])

# name, file, original text (must occur exactly once), mutated text, test group.
MUTANTS = [
    # The seven that survived the suite before tests/test_independent_checks.cpp:
    ("light_term_plus_1pct", ML, "  return r * r;", "  return 1.01 * r * r;", SENSORS),
    ("ground_censoring_removed", FS_G, "      const Censoring c = fit::censoring_at(v[i], 0, full);", "      const Censoring c = Censoring::none;", SENSORS),
    ("diagnose_bic_gate_sign", DE_S, "if (t.delta_bic <= -o_.min_delta_bic) passing", "if (t.delta_bic <= o_.min_delta_bic) passing", DIAGNOSE),
    ("diagnose_heldout_gate_flipped", DE_S, "const bool gain = t.heldout_mse <= current_h_.all * (1.0 - o_.min_heldout_gain);", "const bool gain = t.heldout_mse <= current_h_.all * (1.0 + o_.min_heldout_gain);", DIAGNOSE),
    ("battery_filter_tau_plus_1pct", B, "kFirmwareFilterTau_s = 2.2407;", "kFirmwareFilterTau_s = 2.2631;", BATTERY),
    ("ground_offset_meaning", MG, "  return offset_raw + gain_raw * grey;", "  return offset_raw * (1.0 - grey) + gain_raw * grey;", SENSORS),
    ("tof_offset_inside_scale", MT, "  return scale * distance_m * 1000.0 + offset_mm;", "  return scale * (distance_m * 1000.0 + offset_mm);", SENSORS),
    # Other plausible slips in the models, the fits and the diagnosis's decision rules:
    ("light_rails_not_censored", FS_L, "fit::censoring_at(o.value_raw, 0, full), o.where, group, o.robot});", "fit::censoring_at(o.value_raw, -1.0, full + 1.0), o.where, group, o.robot});", SENSORS),
    ("ground_low_rail_only", FS_G, "      const Censoring c = fit::censoring_at(v[i], 0, full);", "      const Censoring c = fit::censoring_at(v[i], 0, 1e300);", SENSORS),
    ("ground_high_rail_only", FS_G, "      const Censoring c = fit::censoring_at(v[i], 0, full);", "      const Censoring c = fit::censoring_at(v[i], -1e300, full);", SENSORS),
    ("proximity_linear_sign", MP, "return (abc[0] * distance_m + abc[1]) * distance_m + abc[2];", "return (abc[0] * distance_m - abc[1]) * distance_m + abc[2];", SENSORS),
    ("camera_px_sign", MC, "px[0] = cx_px - f_px * x * scale;", "px[0] = cx_px + f_px * x * scale;", SENSORS),
    ("camera_full_angle_focal", MC, "const T f_px = T(width_px / 2.0) / tan(hfov_rad / 2.0);", "const T f_px = T(width_px / 2.0) / tan(hfov_rad);", SENSORS),
    ("tof_floor_censoring_removed", FS_D, "o{tof_channel.on_rails(mm), censoring_at(mm, tof_channel.low_rail,", "o{mm <= tof_channel.low_rail ? mm : tof_channel.on_rails(mm), censoring_at(mm, -HUGE_VAL,", SENSORS),
    ("tof_ceiling_censoring_removed", FS_D, "o{tof_channel.on_rails(mm), censoring_at(mm, tof_channel.low_rail, tof_channel.high_rail)", "o{mm >= tof_channel.high_rail ? mm : tof_channel.on_rails(mm), censoring_at(mm, tof_channel.low_rail, HUGE_VAL)", SENSORS),
    # The censored, robust engine (lib/fit/src/robust.cpp):
    ("tobit_rail_side_flipped", RD, "const double z = sign * (prediction - reading) / sd;", "const double z = -sign * (prediction - reading) / sd;", SENSORS),
    ("outliers_never_left_out", RB, "if (obs[i].censoring == Censoring::none && std::abs(dev) > opt.reject_sd) next[i] = 0;", "if (false) next[i] = 0;", SENSORS),
    ("encoder_unwrap_off_by_one", ME, "if (delta > 32767.0) delta -= 65536.0;", "if (delta > 32767.0) delta -= 65535.0;", SENSORS),
    ("slip_lag_decay_complement", MD, "vg_m_s = u0_m_s + ag_m_s2 * len_s - ag_m_s2 * tau + c * e;", "vg_m_s = u0_m_s + ag_m_s2 * len_s - ag_m_s2 * tau + c * (1.0 - e);", SENSORS),
    ("light_range_ignored", ML, "if (l.intensity > 0 && l.distance_m <= k.range_m) sum +=", "if (l.intensity > 0) sum +=", SENSORS),
    ("battery_lerp_reversed", B, "inline double lerp(double a, double b, double w) { return a + (b - a) * w; }", "inline double lerp(double a, double b, double w) { return a + (b - a) * (1.0 - w); }", BATTERY),
    ("diagnose_bic_margin_default", DH, "double min_delta_bic = 10.0;", "double min_delta_bic = 6.0;", DIAGNOSE),
    ("diagnose_heldout_gain_default", DH, "double min_heldout_gain = 0.03;", "double min_heldout_gain = 0.01;", DIAGNOSE),
    ("diagnose_heldout_gate_ignored", DE_S, "const bool gain = t.heldout_mse <= current_h_.all * (1.0 - o_.min_heldout_gain);", "const bool gain = true;", DIAGNOSE),
    ("diagnose_bic_gate_ignored", DE_S, "if (t.delta_bic <= -o_.min_delta_bic) passing", "if (true) passing", DIAGNOSE),
    ("diagnose_structure_or", DE_RS, "s.significant = s.score >= threshold && chi2 > chi2_critical(df1);", "s.significant = s.score >= threshold || chi2 > chi2_critical(df1);", DIAGNOSE),
    ("battery_transient_no_slope", B, "const double c_tau = q.c * kFirmwareFilterTau_s;", "const double c_tau = 0.0 * kFirmwareFilterTau_s;", BATTERY),
    # Issue #22's fresh slips (bench/fresh-slips.md):
    ("cap_right_uses_left", FS_D, "r = std::clamp(vr[i] / 100.0, -cap, cap);", "r = std::clamp(vl[i] / 100.0, -cap, cap);", CAP),
    ("cap_reverse_uncapped", FS_D, "const double l = std::clamp(vl[i] / 100.0, -cap, cap),", "const double l = std::min(vl[i] / 100.0, cap),", CAP),
    ("cap_count_left_only", FS_D, "if (l != vl[i] / 100.0 || r != vr[i] / 100.0) {", "if (l != vl[i] / 100.0) {", CAP),
    ("unit_s_before_cm_s", LR, 'for (const char* unit : {"cm_s", "mm", "deg", "s", "m", "v"}) {', 'for (const char* unit : {"s", "cm_s", "mm", "deg", "m", "v"}) {', HINTS),
    ("unit_typo_half_rule", LR, "if (d < best_distance && 2 * d < missing.size()) {", "if (d < best_distance && d < missing.size()) {", HINTS),
    ("unit_hint_column_index", LR, "    column = header_columns[best];", "    column = static_cast<int>(best) + 1;", HINTS),
    ("tof_code_dropout_ignored", DK_DRIVE, "const bool dropout = tof_code_in_view(tof[i], 1000.0 * (r.obstacle_m - steps_metres(ul[i], ur[i])));", "const bool dropout = false;", round_two(TOF_CODES, "RoundTwoDiagnosisTofCodes")),
    ("tof_code_as_reading", DK_DRIVE, "{tof_channel.on_rails(tof[i]), ul[i], ur[i]}", "{tof[i], ul[i], ur[i]}", TOF_CODES),
    ("tof_code_strict", LH, "return mm >= kTofOutOfRangeCode_mm;", "return mm > kTofOutOfRangeCode_mm;", TOF_CODES),
    ("noise_dof_no_minus_one", RN, "dof += v.size() - 1;", "dof += v.size();", NOISE),
    ("noise_small_group_le", RN, "g.kept.size() < kSmallGroup ?", "g.kept.size() <= kSmallGroup ?", NOISE),
    ("noise_per_sensor_inverted", RN, "if (key.first != s || v.size() < 2) continue;", "if (key.first == s || v.size() < 2) continue;", NOISE),
    # The reading noise's median is lib/fit's one median (replicates.cpp) since the unity build.
    ("noise_median_even_upper", "lib/fit/src/replicates.cpp", "if (v.size() % 2 == 0) m = 0.5 * (m + ", "if (false) m = 0.5 * (m + ", NOISE),
    ("charge_load_sign", CM, "double x = voltage_v + load_offset_v(m, speed_cm_s);", "double x = voltage_v - load_offset_v(m, speed_cm_s);", CHARGE),
    ("charge_load_lerp_reversed", CM, "return y[k] + (y[k + 1] - y[k]) * (s - x[k]) / (x[k + 1] - x[k]);", "return y[k] + (y[k + 1] - y[k]) * (x[k + 1] - s) / (x[k + 1] - x[k]);", CHARGE),
    ("charge_residual_sd_n", CM, "std::sqrt(c.rss / static_cast<double>(d.v.size() - c.parameters));", "std::sqrt(c.rss / static_cast<double>(d.v.size()));", CHARGE),
    ("charge_clamp_side_high", CM, "    c.side = -1;", "    c.side = 1;", CHARGE),
    ("cluster_no_small_sample", RP, "bread * meat * bread * (g / (g - 1.0));", "bread * meat * bread;", CLUSTER),
    ("cluster_min_le", RP, "if (G < kMinClusters) {", "if (G <= kMinClusters) {", CLUSTER),
    ("cluster_no_floor", RP, "a.std_errors[j] = std::max(se, fit.parameters[j].std_error);", "a.std_errors[j] = se;", CLUSTER),
    ("q_unweighted_mean", RB, "const double xw = swx / sw;", "const double xw = mean;", QTEST),
    ("q_dof_robots", RB, "s.dof = x.size() - 1;", "s.dof = x.size();", QTEST),
    ("q_se_not_squared", RB, "s.q += (x[i] - xw) * (x[i] - xw) / (se[i] * se[i]);", "s.q += (x[i] - xw) * (x[i] - xw) / se[i];", QTEST),
    ("tobit_em_hazard_side", RB, "ss += sigma * sigma * (1 + c * normal_hazard_lower(-c));", "ss += sigma * sigma * (1 + c * normal_hazard_lower(c));", TOBIT),
    ("tobit_loglik_side", RB, "loglik += log_normal_cdf(sign * (predictions[i] - obs[i].value) / sigma);", "loglik += log_normal_cdf(sign * (obs[i].value - predictions[i]) / sigma);", TOBIT),
    ("tobit_gradient_unsigned", RD, "? -scale * normal_hazard_lower(z) / r / sd : 0.0;", "? scale * normal_hazard_lower(z) / r / sd : 0.0;", TOBIT),
    ("codegen_array_first", CG, 'for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + cpp_number(v[i]);', 'for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + cpp_number(v[0]);', CODEGEN),
    ("codegen_ground_gain_offset_swapped", CG, 'cpp_number(m.sensors[k].gain_raw) << ", " << cpp_number(m.sensors[k].offset_raw)', 'cpp_number(m.sensors[k].offset_raw) << ", " << cpp_number(m.sensors[k].gain_raw)', CODEGEN),
    ("codegen_covariate_slope_centre", CG, 'cpp_number(covariates[i].slope) + ", " +\n           cpp_number(covariates[i].centre)', 'cpp_number(covariates[i].centre) + ", " +\n           cpp_number(covariates[i].slope)', CODEGEN),
    ("codegen_parameters_home_dropped", CG, "if (e.home == fx::Home::base) continue;", "if (e.home != fx::Home::effects) continue;", CODEGEN),
    ("identify_wald_no_cross", DK_GROUND, "V(a, b) = cov(ia, ib) - cov(ia, g[0]) - cov(g[0], ib) + cov(g[0], g[0]);", "V(a, b) = cov(ia, ib) + cov(g[0], g[0]);", IDENTIFY),
    ("identify_wald_dof_sensors", DK_GROUND, "const double dof = static_cast<double>(m);", "const double dof = static_cast<double>(m + 1);", IDENTIFY),
    ("identify_level_first_gain", DK_GROUND, "const double level = offset + (values[static_cast<std::size_t>(level_)] - offset) * mean;", "const double level = offset + (values[static_cast<std::size_t>(level_)] - offset) * values[g[0]];", IDENTIFY),
    ("identify_tail_share_strict", DK_PROXIMITY, "tail <= kTailShareOfNearField * total) return std::nullopt;", "tail < kTailShareOfNearField * total) return std::nullopt;", (IDENTIFY[0] + ["test_round_four_slips"], IDENTIFY[1][:-1] + "|RoundFourIdentify)")),
    # Round 2 of the fresh slips (bench/fresh-slips.md), planted without reading the tests:
    ('charge_above_fastest_takes_slowest', CM, '  if (s >= x.back()) return y.back();', '  if (s >= x.back()) return y.front();', round_two(CHARGE, "RoundTwoChargeMap")),
    ('noise_screen_floor_forgotten', RN, 'reject_sd * std::max(pooled_sd, floor_sd)', 'reject_sd * pooled_sd', round_two(NOISE, "RoundTwoReadingNoise")),
    ('noise_whole_integer_division', "lib/diagnose/src/reading_noise.cpp", 'sd * sd - 1.0 / 12.0', 'sd * sd - 1 / 12', ([R2], r"^RoundTwoReadingNoise")),
    ('codegen_camera_cy_from_cx', CG, 'm.base.cy_px = " << cpp_number(m.base.cy_px)', 'm.base.cy_px = " << cpp_number(m.base.cx_px)', round_two(CODEGEN, "RoundTwoCodegen")),
    ('like_camera_py_from_px', SLM, 'out[i] = {p[0] + covariate[i], p[1] + covariate[i]};', 'out[i] = {p[0] + covariate[i], p[0] + covariate[i]};', LIKE),
    ('like_proximity_angle_degrees', SLM, 'std::cos(deg_to_rad(log.col("angle_deg")[i]))', 'std::cos(log.col("angle_deg")[i])', LIKE),
    ('identify_level_offset_dropped', DK_GROUND, 'const double level = offset + (values[static_cast<std::size_t>(level_)] - offset) * mean;', 'const double level = values[static_cast<std::size_t>(level_)] * mean;', round_two(IDENTIFY, "RoundTwoIdentify")),
    ('jackknife_sd_divisor', DE_S, 'std::sqrt((G - 1) / G * ss)', 'std::sqrt(ss / (G - 1))', ([R2], r"^RoundTwoJackknife")),
    ('ar1_factor_no_sqrt', RP, 'a.factor = std::sqrt(nn / a.n_eff);', 'a.factor = nn / a.n_eff;', round_two(CLUSTER, "RoundTwoAutocorrelation")),
    ('q_spread_sd_n', RB, 's.spread_sd = std::sqrt(ss / static_cast<double>(x.size() - 1));', 's.spread_sd = std::sqrt(ss / static_cast<double>(x.size()));', round_two(QTEST, "RoundTwoRobotSpread")),
    ('tobit_loglik_no_log_sigma', RB, 'loglik += -std::log(sigma) - kLogSqrt2Pi - 0.5 * z * z;', 'loglik += -kLogSqrt2Pi - 0.5 * z * z;', round_two(TOBIT, "RoundTwoTobit")),
    ('cap_bic_margin_sign', FS_D, 'out.bic_uncapped <= out.bic_capped - kCapBicMargin', 'out.bic_uncapped <= out.bic_capped + kCapBicMargin', round_two(CAP, "RoundTwoFirmwareCap")),
    ('hint_obstacle_tof_in_mm', "lib/calibrate/src/plausibility.cpp", 'likely_unit(seen ? d / (tof[0] / 1000.0) : d / ceiling_m)', 'likely_unit(seen ? d / tof[0] : d / ceiling_m)', round_two(HINTS, "RoundTwoUnitHints")),
    ('tof_code_view_range_in_m', DK_DRIVE, 'tof_code_in_view(tof[i], 1000.0 * (r.obstacle_m - steps_metres(ul[i], ur[i])))', 'tof_code_in_view(tof[i], r.obstacle_m - steps_metres(ul[i], ur[i]))', round_two(TOF_CODES, "RoundTwoDiagnosisTofCodes")),
    ('model_file_open_lower_ignored', MF, '(p->open_lower ? x > p->lower : x >= p->lower)', 'x >= p->lower', round_two(CODEGEN, "RoundTwoModelFile")),
    # Round 3 of the fresh slips (bench/fresh-slips.md), planted without reading the tests:
    ("r3_charge_flat_knots_refused", CM, "if (m.knot_charge[k] < m.knot_charge[k - 1])", "if (m.knot_charge[k] <= m.knot_charge[k - 1])", R3_CHARGE),
    ("r3_charge_quantile_knots_k", CM, "static_cast<double>(n - 1) / (K - 1)", "static_cast<double>(n - 1) / K", R3_CHARGE),
    ("r3_noise_model_sd_max", DR, "std::min(1.0, residual_sd / n.sd)", "std::max(1.0, residual_sd / n.sd)", R3_NOISE),
    ("r3_noise_sensor_zero_pooled", DR, "if (sensor >= 0 && k < n.per_sensor_sd.size()", "if (sensor > 0 && k < n.per_sensor_sd.size()", R3_NOISE),
    ("r3_codegen_array_last_dropped", CG, 'for (std::size_t i = 0; i < N; ++i) s += (i ? ", " : "") + cpp_number(a[i]);',
     'for (std::size_t i = 0; i + 1 < N; ++i) s += (i ? ", " : "") + cpp_number(a[i]);', R3_CODEGEN),
    ("r3_codegen_drive_encoder_from_tof", CG, '"  m.encoder_noise_sd_steps = " << cpp_number(m.encoder_noise_sd_steps)',
     '"  m.encoder_noise_sd_steps = " << cpp_number(m.tof_noise_sd_mm)', R3_CODEGEN),
    ("r3_like_light_args_swapped", SLM, "return mean_raw(m, sensor, in[i], d[i]);", "return mean_raw(m, sensor, d[i], in[i]);", R3_LIKE),
    ("r3_like_battery_start_last", SLM, 'n ? log.col("charge").front() : 1.0', 'n ? log.col("charge").back() : 1.0', R3_LIKE),
    ("r3_identify_equal_gains_inverted", KG, "if (!(p_value >= kEqualGainsP)) return std::nullopt;", "if (p_value >= kEqualGainsP) return std::nullopt;", R3_DIAGNOSE),
    ("r3_jackknife_three_folds_strict", DE_S, "if (current_h_.fold_values.size() >= 3) {", "if (current_h_.fold_values.size() > 3) {", R3_DIAGNOSE),
    ("r3_cluster_run_zero_dropped", RP, "if (std::isfinite(residuals[i]) && run[i] >= 0) {", "if (std::isfinite(residuals[i]) && run[i] > 0) {", R3_FIT),
    ("r3_q_exceeds_inverted", RB, "s.exceeds = s.p_value < kRobotSpreadP;", "s.exceeds = s.p_value > kRobotSpreadP;", R3_FIT),
    ("r3_tobit_below_reject_sign", RB, "if (obs[i].censoring == Censoring::at_or_below && dev < -opt.reject_sd) next[i] = 0;",
     "if (obs[i].censoring == Censoring::at_or_below && dev > opt.reject_sd) next[i] = 0;", R3_FIT),
    ("r3_cap_commanded_uses_uncapped", FS_D, "if (std::abs(v) > cap) at_cap_steps += 0.5 * std::copysign(s::kFirmwareSpeedLimit_steps_s, v) * dt;",
     "if (std::abs(v) > 1e300) at_cap_steps += 0.5 * std::copysign(s::kFirmwareSpeedLimit_steps_s, v) * dt;", R3_CAP),
    ("r3_argos_ground_noise_scale", AS, 'ConfigureNoise(s, "ground", Sd(m_sModel.noise_sd_raw), ms::kPluginNoiseScaleGround_counts, m_cNoise);',
     'ConfigureNoise(s, "ground", Sd(m_sModel.noise_sd_raw), ms::kPluginNoiseScaleProximity_counts, m_cNoise);', R3_ARGOS),
    ("r3_hint_worst_distance_min", PL, "if (d[i] > d[worst]) worst = i;", "if (d[i] < d[worst]) worst = i;", R3_HINTS),
    ("r3_hint_typo_distance_two", LR, "std::size_t best = 0, best_distance = 3;", "std::size_t best = 0, best_distance = 2;", R3_HINTS),
    ("r3_tof_code_dropout_kept", DK_DRIVE, "const bool fresh[3] = {!dropout,", "const bool fresh[3] = {true,", R3_DIAGNOSE),
    ("r3_model_noise_full_scale_le", MF, "if (!(out[i] >= 0 && out[i] < c.full_scale))", "if (!(out[i] >= 0 && out[i] <= c.full_scale))", R3_MODEL),
    ("r3_model_encoder_noise_from_tof", MF, "m.encoder_noise_sd_steps = d.noise(d.facts().channels[1])[0];",
     "m.encoder_noise_sd_steps = d.noise(d.facts().channels[0])[0];", R3_MODEL),
    # Round 4 of the fresh slips (bench/fresh-slips.md), planted without reading the tests:
    ("r4_readings_low_rail_strict", RD, "  if (value <= low) return Censoring::at_or_below;", "  if (value < low) return Censoring::at_or_below;", R4_FIT),
    ("r4_report_censored_sides_swapped", "lib/calibrate/src/report_json.cpp",
     'd["censored"] = {{"at_or_below", r.censored_below}, {"at_or_above", r.censored_above}};',
     'd["censored"] = {{"at_or_below", r.censored_above}, {"at_or_above", r.censored_below}};', R4_REPORT),
    ("r4_ground_report_offset_se_from_gain", "lib/calibrate/src/ground_report.cpp", 'offset_se.push_back(json_number(r.std_error("offset")));',
     'offset_se.push_back(json_number(r.std_error("gain")));', R4_REPORT),
    ("r4_diagnose_report_smallest_error", "lib/diagnose/src/report_output.cpp", "[](const Error& a, const Error& b) { return a.se < b.se; }",
     "[](const Error& a, const Error& b) { return a.se > b.se; }", R4_DREPORT),
    ("r4_facts_camera_cy_width", "lib/models/include/epuck2/models/kind_facts.hpp",
     '{"cy_px", "px", 0.0, static_cast<double>(s::kCameraHeight_px), false, false}',
     '{"cy_px", "px", 0.0, static_cast<double>(s::kCameraWidth_px), false, false}', R4_FACTS),
    ("r4_model_light_sensor_gamma_zero", MF, "if (!(g > range.lower && g <= range.upper))", "if (!(g >= range.lower && g <= range.upper))", with_round_four(R3_MODEL)),
    ("r4_codegen_battery_moving_from_static", CG, "cpp_number(t.simple_moving_slope_per_s)", "cpp_number(t.simple_static_slope_per_s)", with_round_four(R3_CODEGEN)),
    ("r4_charge_default_range_max_front", CM, "    m.voltage_max_v = m.knots_v.back();", "    m.voltage_max_v = m.knots_v.front();", with_round_four(R3_CHARGE)),
    ("r4_noise_railed_last_reading_only", RN, "g.railed = g.railed || on_rail[i];", "g.railed = on_rail[i];", R4_NOISE),
    ("r4_noise_uniform_level_sqrt12", "lib/models/include/epuck2/models/noise.hpp", "return std::sqrt(3.0) * sd / scale;",
     "return std::sqrt(12.0) * sd / scale;", R4_NOISE),
    ("r4_structure_channel_weight_inverted", DE_RS, "p.channel_min_structure[c] * sigma[0] / sigma[c]",
     "p.channel_min_structure[c] * sigma[c] / sigma[0]", with_round_four(R3_DIAGNOSE)),
    ("r4_identify_tail_unclipped", DK_PROXIMITY,
     "const double t = std::max(0.0, std::min(with[i], s::kProximityFullScale_raw) - std::min(without[i], s::kProximityFullScale_raw));",
     "const double t = std::max(0.0, with[i] - without[i]);", with_round_four(R3_DIAGNOSE)),
    ("r4_like_ground_clamp_proximity_scale", SLM, "log, covariate, kGroundFullScale_raw, noise, normal,", "log, covariate, kProximityFullScale_raw, noise, normal,", R4_LIKE),
    ("r4_cap_uncapped_no_half", FS_D, "run.command_uncapped_m_s.push_back(0.5 * (vl[i] + vr[i]) / 100.0);",
     "run.command_uncapped_m_s.push_back((vl[i] + vr[i]) / 100.0);", with_round_four(R3_CAP)),
    ("r4_tof_code_view_margin_sign", SC, "encoder_range_mm < (1.0 - kTofInViewMargin) * ceiling",
     "encoder_range_mm < (1.0 + kTofInViewMargin) * ceiling", R4_TOF_CODES),
    ("r4_log_sensor_index_one_more", "lib/models/include/epuck2/models/kind_facts.hpp", 'return {"sensor", 0, sensors - 1.0,',
     'return {"sensor", 0, sensors + 0.0,', R4_LOGS),
    ("r4_log_cell_column_zero_based", LR, "static_cast<int>(start) + 1});", "static_cast<int>(start)});", R4_LOGS),
    ("r4_plot_legend_keys_at_left", "lib/plot/src/figure.cpp", "x, std::min(right, x + w), 0.0, top, x, top, font_pt);",
     "x, std::min(right, x + w), 0.0, top, left, top, font_pt);", R4_PLOT),
    ("r4_argos_incidence_frame_not_conjugate", AS, "RotateUnit(cQ.GetW(), -cQ.GetX(), -cQ.GetY(), -cQ.GetZ(), c_hit - sOrigin.Position)",
     "RotateUnit(cQ.GetW(), cQ.GetX(), cQ.GetY(), cQ.GetZ(), c_hit - sOrigin.Position)", R4_ARGOS),
    ("r4_argos_tof_noise_scale_metres", AS, 'ConfigureNoise(s, "tof", {sModel.tof_noise_sd_mm}, m_sCoefficients.range_m * 1000.0, m_cNoise);',
     'ConfigureNoise(s, "tof", {sModel.tof_noise_sd_mm}, m_sCoefficients.range_m, m_cNoise);', R4_ARGOS),
    # Round 5 of the fresh slips (bench/fresh-slips.md), planted without reading the tests:
    ("r5_charge_below_slowest_takes_last", CM, "if (x.size() == 1 || s <= x.front()) return y.front();",
     "if (x.size() == 1 || s <= x.front()) return y.back();", with_round_five(with_round_four(R3_CHARGE))),
    ("r5_dnoise_warning_ratio_inverted", DR, "const double ratio = v.value / it->second.sd;",
     "const double ratio = it->second.sd / v.value;", with_round_five(R4_NOISE)),
    ("r5_codegen_segment_x1_x2_swapped", CG, 'cpp_number(g.x1_s) << ", " << cpp_number(g.x2_s)',
     'cpp_number(g.x2_s) << ", " << cpp_number(g.x1_s)', with_round_five(with_round_four(R3_CODEGEN))),
    ("r5_model_noise_sd_largest_not_rms", MF, 'c["sd"] = same ? sd[0] : rms;', 'c["sd"] = same ? sd[0] : top;', with_round_five(R5_FACTS)),
    ("r5_like_drive_wheels_swapped", SLM, "out[i] = {static_cast<double>(r.left_steps), static_cast<double>(r.right_steps),",
     "out[i] = {static_cast<double>(r.right_steps), static_cast<double>(r.left_steps),", with_round_five(R4_LIKE)),
    ("r5_identify_tail_total_without", DK_PROXIMITY, "total += std::max(0.0, std::min(with[i], s::kProximityFullScale_raw));",
     "total += std::max(0.0, std::min(without[i], s::kProximityFullScale_raw));", with_round_five(with_round_four(R3_DIAGNOSE))),
    ("r5_structure_df1_bins", DE_RS, "const double df1 = static_cast<double>(used - 1),",
     "const double df1 = static_cast<double>(used),", with_round_five(with_round_four(R3_DIAGNOSE))),
    ("r5_jackknife_mean_divisor", DE_S, "mean += v[static_cast<std::size_t>(j)] / G;",
     "mean += v[static_cast<std::size_t>(j)] / (G - 1);", with_round_five(with_round_four(R3_DIAGNOSE))),
    ("r5_ar1_neff_inverted", RP, "std::clamp(nn * (1.0 - a.rho) / (1.0 + a.rho), 1.0, nn);",
     "std::clamp(nn * (1.0 + a.rho) / (1.0 - a.rho), 1.0, nn);", with_round_five(R4_FIT)),
    ("r5_tobit_hazard_tail_sign", RD, "return -z / (1 - 1 / z2 + 3 / (z2 * z2) - 15 / (z2 * z2 * z2));",
     "return z / (1 - 1 / z2 + 3 / (z2 * z2) - 15 / (z2 * z2 * z2));", with_round_five(R4_FIT)),
    ("r5_q_two_robots_skipped", RB, "if (x.size() < 2) continue;", "if (x.size() < 3) continue;", with_round_five(R4_FIT)),
    ("r5_cap_one_row_not_tested", FS_D, "if (out.capped_rows > 0) {", "if (out.capped_rows > 1) {", with_round_five(with_round_four(R3_CAP))),
    ("r5_tof_code_range_sign", DK_DRIVE, "1000.0 * (r.obstacle_m - steps_metres(ul[i], ur[i]))",
     "1000.0 * (r.obstacle_m + steps_metres(ul[i], ur[i]))", with_round_five(R4_TOF_CODES)),
    ("r5_argos_uniform_level_first_sensor", AS, "vecLevel.push_back(ms::uniform_level_with_sd(fSd, f_scale));",
     "vecLevel.push_back(ms::uniform_level_with_sd(vec_sd.front(), f_scale));", with_round_five(R4_ARGOS)),
    ("r5_log_forward_zero_accepted", "lib/models/include/epuck2/models/kind_facts.hpp",
     '{"forward_m", 1e-12, 1e3, "a forward distance in (0, 1000] m"}', '{"forward_m", 0.0, 1e3, "a forward distance in (0, 1000] m"}',
     with_round_five(R4_LOGS)),
    ("r5_hint_unit_with_underscore", LR, 'has the unit " + h.substr(quantity.size() + 1) + "; this column',
     'has the unit " + h.substr(quantity.size()) + "; this column', with_round_five(R4_LOGS)),
    ("r5_facts_ground_names_reversed", "lib/models/include/epuck2/models/kind_facts.hpp", '{"0 (right)", "1 (centre)", "2 (left)"}',
     '{"0 (left)", "1 (centre)", "2 (right)"}', with_round_five(R5_FACTS)),
    ("r5_effects_neutral_not_admissible", "lib/models/include/epuck2/models/effects.hpp",
     "return value == p.neutral || (value >= p.lower && value <= p.upper);", "return value >= p.lower && value <= p.upper;", with_round_five(R5_FACTS)),
    ("r5_drive_report_steps_observations_from_tof", "lib/calibrate/src/drive_report.cpp", 'j["steps_observations"] = f.steps.observations;',
     'j["steps_observations"] = f.tof.observations;', with_round_five(R4_REPORT)),
    ("r5_dreport_structure_before_as_after", "lib/diagnose/src/report_output.cpp", 'j["residual_structure"] = scores(r.structure_after);',
     'j["residual_structure"] = scores(r.structure_before);', with_round_five(R4_DREPORT)),
    # One light model everywhere (issue #22): a sensor's own gamma dropped from the model's formula
    # (simulate --like, codegen's model, the diagnosis's base and ARGoS would take the pooled one).
    ("lg_light_sensor_gamma_ignored", "lib/models/include/epuck2/models/kinds.hpp", "  k.gamma_m = light_gamma_m(m, sensor);",
     "  k.gamma_m = m.base.gamma_m;", whole(R3_ALWAYS + ["test_light_gammas", "test_model_sets", "test_round_four_slips",
                                                         "test_strict_files"])),
    # The engine's one identifiability check (lib/fit/src/least_squares.cpp), used by the calibration
    # (hold at the fallback, refit) and by every other fit (an explained NaN).
    ("e7_identifiability_zero_column_unseen", "lib/fit/src/least_squares.cpp", "if (jacobian.col(j).squaredNorm() > 0)",
     "if (jacobian.col(j).squaredNorm() >= 0)", whole(list(R3_FIT[1][1]) + ["test_one_engine", "test_diagnose"])),
    ("e7_identifiability_condition_ignored", "lib/fit/src/least_squares.cpp", "weak = weak || !(id.condition <= max_condition);",
     "weak = weak || !(id.condition <= 1e6 * max_condition);", whole(list(R3_FIT[1][1]) + ["test_one_engine", "test_diagnose"])),
    # Round 6: slips of the survivors' classes (bench/fresh-slips.md, "Classes of survivors").
    # A: a field written with its sibling's value, checked only by stability comparisons.
    ("c6_codegen_light_range_from_gamma", CG, r'<< ";\n  m.base.range_m = " << cpp_number(m.base.range_m)',
     r'<< ";\n  m.base.range_m = " << cpp_number(m.base.gamma_m)', C6_CODEGEN),
    ("c6_drive_report_steps_mse_from_tof", "lib/calibrate/src/drive_report.cpp", 'j["steps_mse"] = f.steps.mse;',
     'j["steps_mse"] = f.tof.mse;', C6_REPORT),
    ("c6_proximity_points_min_from_mean", "lib/calibrate/src/proximity_report.cpp", '{"mean", p.mean}, {"min", p.min}',
     '{"mean", p.mean}, {"min", p.mean}', C6_REPORT),
    ("c6_dreport_heldout_recalibrated_from_plugin", "lib/diagnose/src/report_output.cpp",
     'j["heldout_mse_recalibrated"] = r.heldout_mse_base;', 'j["heldout_mse_recalibrated"] = r.heldout_mse_plugin;', C6_DREPORT),
    # B: per-sensor values equal in every fixture (an index swap, sensor 0 or the pooled value for all).
    ("c6_ground_report_n_sensor0", "lib/calibrate/src/ground_report.cpp", "n.push_back(r.observations);",
     "n.push_back(f.sensors[0].observations);", C6_REPORT),
    ("c6_ground_report_mse_pooled", "lib/calibrate/src/ground_report.cpp", "mse.push_back(r.mse);", "mse.push_back(f.mse);", C6_REPORT),
    ("c6_light_report_sensor_mse_pooled", "lib/calibrate/src/light_report.cpp", '{"mse", json_number(r.mse)}',
     '{"mse", json_number(f.gamma.mse)}', C6_REPORT),
    ("c6_codegen_effect_array_first", CG, 'for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + cpp_number(v[i]);',
     'for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + cpp_number(v[0]);', C6_CODEGEN),
    ("c6_like_sensor_first_row", SLM, "const int sensor = static_cast<int>(sn[i]);", "const int sensor = static_cast<int>(sn[0]);", C6_LIKE),
    # C: a boundary the code branches on that no test sits on.
    ("c6_model_open_upper_ignored", MF, "(p->open_upper ? x < p->upper : x <= p->upper)", "(x <= p->upper)", C6_MODEL),
    ("c6_log_metadata_low_strict", LR, "if (d < meta.lo || d > meta.hi) {", "if (d <= meta.lo || d > meta.hi) {", C6_LOGS),
    ("c6_light_censored_zero_strict", FS_L, "if (v[i] <= 0 || v[i] >= s::kProximityFullScale_raw) ++out.censored;",
     "if (v[i] < 0 || v[i] >= s::kProximityFullScale_raw) ++out.censored;", C6_FIT),
    # E: an option's non-default value never given (the user's --reject-sd dropped).
    ("c6_sensor_reject_sd_ignored", "lib/calibrate/src/sensor_fit_common.cpp", "  r.reject_sd = o.reject_sd;\n", "", C6_FIT),
    # D: a statistic's degrees of freedom (added after both c6 runs: judged by neither, see bench/fresh-slips.md).
    ("c6_stat_reduced_chi2_no_k", RP, "s.reduced_chi2 = nn > k ? rss / (nn - k) : kNaN;", "s.reduced_chi2 = nn > k ? rss / nn : kNaN;", C6_FIT),
    # Round 7 of the fresh slips (bench/fresh-slips.md), planted without reading the tests:
    ("r7_covariance_permutation_transposed", "lib/fit/src/least_squares.cpp",
     "return scale.asDiagonal() * (P * inner * P.transpose()) * scale.asDiagonal();",
     "return scale.asDiagonal() * (P.transpose() * inner * P) * scale.asDiagonal();", R7_FIT),
    ("r7_jet_erfc_derivative_sign", "lib/fit/include/epuck2/fit/jet.hpp", "return Jet<N>(erfc(x.a), -x.v * exp(-x.a * x.a)",
     "return Jet<N>(erfc(x.a), x.v * exp(-x.a * x.a)", R7_JET),
    ("r7_channels_sd_and_scale_swapped", RD, "return reading_residual(prediction, at, censoring, sd_[c], sd_[0]);",
     "return reading_residual(prediction, at, censoring, sd_[0], sd_[c]);", R7_FIT),
    ("r7_active_set_upper_held_at_lower", "lib/fit/src/fit_curve.cpp", "        initial[j] = hi;\n", "        initial[j] = lo;\n", R7_FIT),
    ("r7_problem_lower_bound_sets_upper", "lib/fit/src/problem.cpp",
     "void Problem::set_lower_bound(double* block, int index, double value) { impl_->problem.SetParameterLowerBound(block, index, value); }",
     "void Problem::set_lower_bound(double* block, int index, double value) { impl_->problem.SetParameterUpperBound(block, index, value); }",
     R7_FIT),
    ("r7_calibration_mean_c_from_maxima", MF, 'j["parameters"]["mean_c"] = means.base.c;', 'j["parameters"]["mean_c"] = maxima.base.c;', R7_COEFF),
    ("r7_battery_segment_y2_from_y1", "lib/coefficients/src/battery_tables.cpp", '{"y1", g.y1}, {"y2", g.y2}', '{"y1", g.y1}, {"y2", g.y1}',
     R7_COEFF),
    ("r7_codegen_camera_range_inverted", CG, "(m.base.range_m != s::kCameraRange_m ?", "(m.base.range_m == s::kCameraRange_m ?", R7_COEFF),
    ("r7_light_gamma_ratio_inverted", "lib/models/include/epuck2/models/kinds.hpp",
     "light_gamma_ratio(const LightModel& m, int sensor) { return light_gamma_m(m, sensor) / m.base.gamma_m; }",
     "light_gamma_ratio(const LightModel& m, int sensor) { return m.base.gamma_m / light_gamma_m(m, sensor); }", R7_MODELS),
    ("r7_effects_tail_length_param_index", "lib/models/include/epuck2/models/effects.hpp", ", 1, 0, e.tail.length_m);",
     ", 0, 0, e.tail.length_m);", R7_MODELS),  # the tail's length given parameter index 0 (its amplitude's)
    ("r7_like_drive_noisy_wheels_swapped", SLM, "sim.sample(t[i], cl[i], cr[i], normal, covariate[i])",
     "sim.sample(t[i], cr[i], cl[i], normal, covariate[i])", R7_MODELS),
    ("r7_battery_lifetime_h_in_minutes", "lib/calibrate/src/battery_json.cpp", '{"lifetime_h", s.lifetime_s / 3600.0}',
     '{"lifetime_h", s.lifetime_s / 60.0}', R7_CALIB),
    ("r7_camera_aperture_se_degree_step", "lib/calibrate/src/camera_report.cpp", "/ (2 * s::deg_to_rad(h));", "/ (2 * h);", R7_CALIB),
    ("r7_enough_rows_strict", DE_S, "if (report_.rows >= report_.minimum_rows", "if (report_.rows > report_.minimum_rows", R7_DIAGNOSE),
    ("r7_structure_size_not_sqrt", DE_RS, "s.size = std::sqrt(between / static_cast<double>(n));", "s.size = between / static_cast<double>(n);",
     R7_DIAGNOSE),
    ("r7_dreport_final_fit_from_base", "lib/diagnose/src/report_output.cpp", '{"final", calibrate::statistics_json(r.final_fit, rss_unit)}',
     '{"final", calibrate::statistics_json(r.base_fit, rss_unit)}', R7_DIAGNOSE),
    ("r7_log_equal_times_refused", LR, "if (previous && values[j][i] < values[j][*previous])",
     "if (previous && values[j][i] <= values[j][*previous])", R7_LOGS),
    ("r7_effects_list_name_last_char_dropped", "apps/cmd_diagnose.cpp", "comma == std::string::npos ? std::string::npos : comma - from)",
     "comma == std::string::npos ? std::string::npos : comma - from - 1)", R7_APPS),
    ("r7_stdout_errno_never_kept", "apps/app_support.cpp", "if (standard_output_errno == 0) standard_output_errno",
     "if (standard_output_errno != 0) standard_output_errno", R7_APPS),
    ("r7_argos_light_sensor_zero_model", AS, "ms::mean_raw(m_sModel, static_cast<int>(i), vecLights)", "ms::mean_raw(m_sModel, 0, vecLights)",
     R7_ARGOS),
    # Session 8 (bench/fresh-slips.md, "Classes closed (session 8)"): one slip of each class planted by
    # hand against tests/test_classes_eight.cpp, in places no round had slipped (not a fresh round).
    ("c8_ground_noisy_sd_sensor0", "lib/models/include/epuck2/models/kinds.hpp",
     "m.noise_sd_raw[static_cast<std::size_t>(sensor)], 0.0,\n                        kGroundFullScale_raw",
     "m.noise_sd_raw[0], 0.0,\n                        kGroundFullScale_raw", R7_MODELS),
    ("c8_like_light_noisy_intensity_distance_swapped", SLM, "reading(m, sensor, in[i], d[i], g, covariate[i])",
     "reading(m, sensor, d[i], in[i], g, covariate[i])", R7_MODELS),
    ("c8_like_proximity_noisy_angle_dropped", SLM, "reading(m, sensor, d[i], cos_incidence(i), g, covariate[i])",
     "reading(m, sensor, d[i], 1.0, g, covariate[i])", R7_MODELS),
    ("c8_camera_noisy_py_from_px", "lib/models/include/epuck2/models/kinds.hpp", "noisy_register(p[1] + covariate_px",
     "noisy_register(p[0] + covariate_px", R7_MODELS),
    ("c8_drive_tof_noise_from_encoders", "lib/models/include/epuck2/models/kinds.hpp", "r.tof_mm = noisy_register(tof, m_.tof_noise_sd_mm,",
     "r.tof_mm = noisy_register(tof, m_.encoder_noise_sd_steps,", R7_MODELS),
    ("c8_battery_noise_squared", "lib/models/include/epuck2/models/kinds.hpp",
     "const double noise = m.noise_sd > 0 ? m.noise_sd * normal() : 0.0;",
     "const double noise = m.noise_sd > 0 ? m.noise_sd * m.noise_sd * normal() : 0.0;", R7_MODELS),
    ("c8_noise_per_sensor_key_missed", MF, '    if (n > 1 && e->contains("per_sensor_sd")) {', '    if (n > 1 && e->contains("per_sensor_sd_")) {', R7_COEFF),
    ("c8_dreport_finding_before_from_after", "lib/diagnose/src/report_output.cpp", 'fj["heldout_mse_before"] = f.heldout_mse_before;',
     'fj["heldout_mse_before"] = f.heldout_mse_after;', R7_DIAGNOSE),
    ("c8_extended_camera_cy_from_dx", "lib/diagnose/src/extended_model.cpp",
     "s::kCameraHeight_px / 2.0 + v.at(principal.name, principal.params[1].key",
     "s::kCameraHeight_px / 2.0 + v.at(principal.name, principal.params[0].key", R7_DIAGNOSE),
    ("c8_dreport_heldout_final_from_base", "lib/diagnose/src/report_output.cpp", 'j["heldout_mse_final"] = r.heldout_mse_final;',
     'j["heldout_mse_final"] = r.heldout_mse_base;', R7_DIAGNOSE),
    ("c8_std_errors_first_parameters", "lib/calibrate/src/report_json.cpp", 'j["std_errors"][prefix + p.name] = json_number(p.std_error);',
     'j["std_errors"][prefix + p.name] = json_number(r.parameters.front().std_error);', R7_CALIB),
    ("c8_stat_aic_from_bic", "lib/calibrate/src/report_json.cpp", '{"aic", json_number(s.aic)},', '{"aic", json_number(s.bic)},', R7_CALIB),
    ("c8_battery_linear_slope_se_over_l", "lib/calibrate/src/battery_fit.cpp", "s.linear_slope_std_error = s.lifetime_std_error_s / (L * L);",
     "s.linear_slope_std_error = s.lifetime_std_error_s / L;", R7_CALIB),
    ("c8_cluster_min_runs_strict", "lib/fit/src/report.cpp", "if (G < kMinClusters) {", "if (G <= kMinClusters) {", R7_FIT),
    ("c8_drive_right_command_in_cm_s", "lib/calibrate/src/drive_fit.cpp", "r = std::clamp(vr[i] / 100.0, -cap, cap);",
     "r = std::clamp(vr[i], -cap, cap);", R7_CALIB),
    ("c8_drive_tof_scale_offset_swapped", "lib/calibrate/src/drive_fit.cpp",
     "out[i++] = s::tof_response_mm(p[1], p[0], T(run.obstacle_distance_m) - travel[k]);",
     "out[i++] = s::tof_response_mm(p[0], p[1], T(run.obstacle_distance_m) - travel[k]);", R7_CALIB),
    ("c8_drive_still_readings_strict", "lib/calibrate/src/drive_fit.cpp",
     "  if (!(out.tof_noise.n >= kMinStillReadings) || !std::isfinite(out.tof_noise.sd))",
     "  if (!(out.tof_noise.n > kMinStillReadings) || !std::isfinite(out.tof_noise.sd))", R7_CALIB),
    ("c8_noise_small_group_le", "lib/calibrate/src/reading_noise.cpp", "g.kept.size() < kSmallGroup ?", "g.kept.size() <= kSmallGroup ?",
     R7_CALIB),
    ("c8_noise_pairs_not_pooled", "lib/calibrate/src/reading_noise.cpp", "if (v.size() < 2) continue;", "if (v.size() <= 2) continue;",
     R7_CALIB),
    # Round 8 (bench/fresh-slips.md, "Round 8"): fresh slips, planted without reading the tests.
    ("r8_jet_reciprocal_not_squared", "lib/fit/include/epuck2/fit/jet.hpp", "const double minus_s_g_a_inverse2 = -s / (g.a * g.a);",
     "const double minus_s_g_a_inverse2 = -s / g.a;", R8_JET),
    ("r8_channels_weight_inverted", RD, "weight_[c] = sd_[0] / sd_[c];", "weight_[c] = sd_[c] / sd_[0];", R8_FIT),
    ("r8_fit_curve_aic_counts_held", "lib/fit/src/fit_curve.cpp", "r.aic = akaike(r.observations, r.rss, free);",
     "r.aic = akaike(r.observations, r.rss, P);", R8_FIT),
    ("r8_ar1_lag_across_runs", RP, "if (i + 1 < e.size() && series[i + 1] == series[i] && std::isfinite(e[i + 1])) {",
     "if (i + 1 < e.size() && std::isfinite(e[i + 1])) {", R8_FIT),
    # (r8_robot_set_checked_as_base, `model_from_json(kind, j, ..., id)` -> `..., "")`, was withdrawn: every
    # reader reads every set of the file whichever it is asked for (every_set), so it changes nothing.)
    ("r8_model_pooled_sd_negative_accepted", MF, "if (!(all >= 0 && all < c.full_scale))", "if (!(all < c.full_scale))", R8_COEFF),
    ("r8_noise_per_sensor_written_when_same", MF, 'if (!same) c["per_sensor_sd"] = sd;', 'if (same) c["per_sensor_sd"] = sd;', R8_COEFF),
    ("r8_battery_cubic_b_c_swapped", "lib/coefficients/src/battery_tables.cpp", '{"cubic", {cubic.d, cubic.c, cubic.b, cubic.a}},',
     '{"cubic", {cubic.d, cubic.b, cubic.c, cubic.a}},', R8_COEFF),
    # (r8_charge_speed_not_absolute, `{v[i], std::abs(s[i]), q[i]}` -> `{v[i], s[i], q[i]}`, was withdrawn: every
    # use of a sample's speed takes its magnitude again (speed_key, load_offset_v), so it changes nothing.)
    ("r8_charge_offset_speed_signed", CM, "const double s = std::abs(speed_cm_s);", "const double s = speed_cm_s;", R8_CALIB),
    ("r8_noise_per_sensor_n_pooled", RN, "r.per_sensor_n.push_back(mine ? n : 0);", "r.per_sensor_n.push_back(mine ? all.n : 0);",
     R8_CALIB),
    ("r8_proximity_point_mean_censoring_from_max", "lib/calibrate/src/proximity_report.cpp", '{"mean_censoring", rail(p.mean_censoring)}',
     '{"mean_censoring", rail(p.max_censoring)}', R8_CALIB),
    ("r8_min_rows_one_fold", DE_S, "report_.minimum_rows = std::max(blocks, folds * per_fold);",
     "report_.minimum_rows = std::max(blocks, per_fold);", R8_DIAGNOSE),
    ("r8_structure_value_bins_strict", DE_RS, "if (distinct <= kMaxValueBins) {", "if (distinct < kMaxValueBins) {", R8_DIAGNOSE),
    ("r8_dreport_censored_above_from_below", "lib/diagnose/src/report_output.cpp",
     'j["censored_per_rail"] = {{"at_or_below", r.censored_below}, {"at_or_above", r.censored_above}};',
     'j["censored_per_rail"] = {{"at_or_below", r.censored_below}, {"at_or_above", r.censored_below}};', R8_DIAGNOSE),
    ("r8_identify_mean_over_all_sensors", DK_GROUND, "for (std::size_t j : g) mean += values[j] / static_cast<double>(g.size());",
     "for (std::size_t j : g) mean += values[j] / static_cast<double>(s::kGroundCount);", R8_DIAGNOSE),
    ("r8_hint_distance_midrange_dropped", PL, "likely_unit(d[worst] / (2 * range_m))", "likely_unit(d[worst] / range_m)", R8_HINTS),
    ("r8_like_seed_metadata_inverted", "apps/cmd_simulate_like.cpp", 'if (noisy) w.metadata("seed", std::to_string(o.seed));',
     'if (!noisy) w.metadata("seed", std::to_string(o.seed));', R8_APPS),
    ("r8_argos_camera_file_range_ignored", AS, "m_fRange = cFileRange ? *cFileRange : m_pcCamEntity->GetRange();",
     "m_fRange = m_pcCamEntity->GetRange();", R8_ARGOS),
    # Classes of round 8's survivors closed elsewhere (bench/fresh-slips.md, "Classes closed (session
    # 11)"): planted by the author of tests/test_classes_nine.cpp and argos/tests/proximity_range.sh,
    # who had read the tests -- not a fresh round.
    ("c9_lof_dof_lack_counts_groups", RB, "  lof.dof_lack = g - k;", "  lof.dof_lack = g;", R8_FIT),
    ("c9_lof_misfit_rms_per_group", RB, "  lof.misfit_rms = std::sqrt(ss_lack / static_cast<double>(count));",
     "  lof.misfit_rms = std::sqrt(ss_lack / static_cast<double>(g));", R8_FIT),
    ("c9_lof_known_noise_subtracts_pure", RB, "  const double ss_lack = std::max(ss_resid - (known ? 0.0 : ss_pure), 0.0);",
     "  const double ss_lack = std::max(ss_resid - ss_pure, 0.0);", R8_FIT),
    ("c9_robust_noise_not_counted", RB, "const double nparams = static_cast<double>(k + (sigma_given ? 0 : 1));",
     "const double nparams = static_cast<double>(k);", R8_FIT),
    ("c9_robust_bic_every_reading", RB, "nparams * std::log(static_cast<double>(std::max<std::size_t>(kept, 1)))",
     "nparams * std::log(static_cast<double>(std::max<std::size_t>(n, 1)))", R8_FIT),
    ("c9_huber_scale_forgotten", "lib/fit/src/least_squares.cpp",
     "  return options.robust ? new ceres::HuberLoss(options.robust_scale) : nullptr;",
     "  return options.robust ? new ceres::HuberLoss(1.0) : nullptr;", R8_FIT),
    ("c9_hint_centimetres_from_30", PL, '  if (factor > 30 && factor < 300) return "centimetres?";',
     '  if (factor >= 30 && factor < 300) return "centimetres?";', R8_HINTS),
    ("c9_obstacle_unseen_against_reading", PL, "likely_unit(seen ? d / (tof[0] / 1000.0) : d / ceiling_m)",
     "likely_unit(d / (tof[0] / 1000.0))", R8_HINTS),
    ("c9_simple_moving_se_over_sqrt_n", "lib/calibrate/src/battery_fit.cpp",
     "const double se_mean = std::sqrt(moving_var) / static_cast<double>(moving.size());",
     "const double se_mean = std::sqrt(moving_var / static_cast<double>(moving.size()));", R8_CALIB),
    ("c9_battery_mse_summed_not_averaged", "lib/calibrate/src/battery_fit.cpp",
     "    out.mse.get(m) = out.speeds.empty() ? 0.0 : sum / static_cast<double>(out.speeds.size());",
     "    out.mse.get(m) = out.speeds.empty() ? 0.0 : sum;", R8_CALIB),
    ("c9_argos_proximity_reach_plugin", AS, "    Real fReach = m_sModel.base.range_m;", "    Real fReach = 0.05;", R8_ARGOS),
    # The three lib/models headers last: each rebuilds most test programs (about 15 minutes a slip here).
    ("r8_pooled_gamma_drops_ratio", "lib/models/include/epuck2/models/kinds.hpp",
     "if (m.sensor_gamma_m[k]) m.sensor_gamma_m[k] = gamma_m * light_gamma_ratio(m, static_cast<int>(k));",
     "if (m.sensor_gamma_m[k]) m.sensor_gamma_m[k] = gamma_m;", R8_MODELS),
    ("r8_like_camera_row_clamped_to_width", SLM, "out[i][1] = std::clamp(out[i][1], 0.0, m.base.height_px - 1.0);",
     "out[i][1] = std::clamp(out[i][1], 0.0, m.base.width_px - 1.0);", R8_MODELS),
    ("r8_facts_light_distance_zero_accepted", "lib/models/include/epuck2/models/kind_facts.hpp",
     '{"distance_m", 1e-3, 1e3, "a distance from the light source', '{"distance_m", 0, 1e3, "a distance from the light source', R8_FACTS),
    # Round 9 (bench/fresh-slips.md, "Round 9"): fresh slips, planted without reading the tests; the
    # three lib/models header slips first (each rebuilds most test programs).
    ("r9_facts_grey_percent_accepted", "lib/models/include/epuck2/models/kind_facts.hpp", '{"grey", 0, 1, "a grey level in [0, 1]"}',
     '{"grey", 0, 100, "a grey level in [0, 1]"}', R9_FACTS),
    ("r9_like_noiseless_covariate_dropped", SLM, ": std::clamp(mean(i, sensor) + covariate[i], 0.0, full_scale)};",
     ": std::clamp(mean(i, sensor), 0.0, full_scale)};", R9_MODELS),
    ("r9_camera_sees_range_along_ray", MC, "&& forward_m < range_m;", "&& norm < range_m;", R9_CAMERA),
    ("r9_condition_not_squared", "lib/fit/src/least_squares.cpp", "return lo > 0 ? (hi / lo) * (hi / lo) :", "return lo > 0 ? hi / lo :",
     R9_FIT),
    ("r9_error_two_digits_at_100", RP, "if (m >= 100) {", "if (m > 100) {", R9_FIT),
    ("r9_correlations_negative_dropped", RP, "std::abs(r(i, j)) > min_abs", "r(i, j) > min_abs", R9_FIT),
    ("r9_lack_of_fit_dof_pure_minus_one", RB, "lof.dof_pure = known ? known_dof_pure : count - g;",
     "lof.dof_pure = known ? known_dof_pure : count - 1;", R9_FIT),
    ("r9_light_per_sensor_duplicate_accepted", MF, "if (m.sensor_gamma_m[static_cast<std::size_t>(k)])\n      d.fail(",
     "if (false)\n      d.fail(", R9_COEFF),
    ("r9_camera_range_zero_accepted", MF, "!(m.base.range_m > 0 && m.base.range_m <= kCameraMaxRange_m)",
     "!(m.base.range_m >= 0 && m.base.range_m <= kCameraMaxRange_m)", R9_COEFF),
    ("r9_battery_noise_rms_over_n", MF, "m.noise_sd = n > 0 ? std::sqrt(sum / n) : 0.0;", "m.noise_sd = n > 0 ? std::sqrt(sum) / n : 0.0;",
     R9_COEFF),
    ("r9_codegen_lifetime_first_speed", CG, "cpp_number(t.lifetime_s[static_cast<std::size_t>(sp)])", "cpp_number(t.lifetime_s[0])",
     R9_COEFF),
    ("r9_light_report_gamma_by_position", "lib/calibrate/src/light_report.cpp",
     "model.sensor_gamma_m.at(static_cast<std::size_t>(f.sensors[i]))", "model.sensor_gamma_m.at(i)", R9_CALIB),
    ("r9_battery_lifetime_se_is_sd", "lib/calibrate/src/battery_fit.cpp",
     "return std::sqrt(ss / static_cast<double>(v.size() - 1) / static_cast<double>(v.size()));",
     "return std::sqrt(ss / static_cast<double>(v.size() - 1));", R9_CALIB),
    ("r9_diagnose_camera_cy_base_from_width", DK_CAMERA, "set_base(*this, dy_, m.base.cy_px - s::kCameraHeight_px / 2.0);",
     "set_base(*this, dy_, m.base.cy_px - s::kCameraWidth_px / 2.0);", R9_DIAGNOSE),
    ("r9_finding_undetermined_signed", DE_S, "if (!(std::abs(v.std_error) <= std::abs(v.value)))", "if (!(v.std_error <= v.value))",
     R9_DIAGNOSE),
    ("r9_log_angle_not_required_checked", LR, '|| cname == "angle_deg" || cname == "voltage_v";', '|| cname == "voltage_v";', R9_LOGS),
    ("r9_log_metadata_upper_unchecked", LR, "if (d < meta.lo || d > meta.hi) {", "if (d < meta.lo) {", R9_LOGS),
    ("r9_simulate_profile_speed_signed", "apps/cmd_simulate.cpp", "profile.push_back({t[i], std::abs(v[i])});",
     "profile.push_back({t[i], v[i]});", R9_APPS),
    ("r9_simulate_default_tables_swapped", "apps/cmd_simulate.cpp", 'if (source.empty()) source = argos ? "plugin" : "fitted";',
     'if (source.empty()) source = argos ? "fitted" : "plugin";', R9_APPS),
    ("r9_argos_tail_reach_one_count", AS, "std::log(2.0 * std::abs(sTail.amplitude_raw))", "std::log(std::abs(sTail.amplitude_raw))",
     R9_ARGOS),
    # Round 10 (bench/fresh-slips.md), planted without reading the tests; the lib/models headers first.
    ("r10_discharge_argos_command_one_tick_early", "lib/models/include/epuck2/models/battery_simulation.hpp",
     "cursor.speed_at(static_cast<double>(k - 2) * dt_s)", "cursor.speed_at(static_cast<double>(k - 1) * dt_s)", R10_DISCHARGE),
    ("r10_light_mean_range_edge_excluded", ML, "if (distance_m <= range_m && intensity > 0) {",
     "if (distance_m < range_m && intensity > 0) {", R10_MODELS),
    ("r10_ground_mean_grey_zero_through_log", MG, "if (!(grey > 0)) return ground_response(gain_raw, offset_raw, 0.0);",
     "if (!(grey >= 0)) return ground_response(gain_raw, offset_raw, 0.0);", R10_MODELS),
    ("r10_argos_tof_delay_pops_past_when", "argos/src/calibrated_drive.hpp",
     "while (past_.size() > 2 && past_[1].first <= when) past_.pop_front();",
     "while (past_.size() > 2 && past_[0].first <= when) past_.pop_front();", R10_ARGOS),
    ("r10_argos_firmware_cap_attribute_inverted", "argos/src/calibrated_actuator.cpp",
     'if (!bFirmwareCap && sConfig.limit_from == "firmware") {', 'if (bFirmwareCap && sConfig.limit_from == "firmware") {', R10_ARGOS),
    ("r10_fit_held_residual_variance_all_params", "lib/fit/src/fit_curve.cpp",
     "r.residual_variance = n > free ? r.rss / (n - free) : r.residual_variance;",
     "r.residual_variance = n > free ? r.rss / (n - P) : r.residual_variance;", R10_FIT),
    ("r10_wild_replicates_typical_floor_dropped", "lib/fit/src/replicates.cpp",
     "const double sd = std::max({sd_of.count(g) ? sd_of.at(g) : typical, 0.5 * typical, floor_sd});",
     "const double sd = std::max({sd_of.count(g) ? sd_of.at(g) : typical, floor_sd});", R10_FIT),
    ("r10_robot_map_star_one_character", "lib/coefficients/src/model_sets.cpp", "(*text != '\\0' && glob_match(pattern, text + 1))",
     "(*text != '\\0' && glob_match(pattern + 1, text + 1))", R10_COEFF),
    ("r10_pooled_set_warning_from_three_robots", "lib/coefficients/src/model_sets.cpp",
     "if (!attribute.empty() || !robots.is_object() || robots.size() < 2) return c;",
     "if (!attribute.empty() || !robots.is_object() || robots.size() <= 2) return c;", R10_COEFF),
    ("r10_battery_cubic_range_end_unchecked", "lib/coefficients/src/battery_tables.cpp", "for (int i = 0; i <= 64; ++i) {",
     "for (int i = 0; i < 64; ++i) {", R10_COEFF),
    ("r10_camera_table4_alpha_sd_over_n", "lib/calibrate/src/camera_fit.cpp", "std::sqrt(ss / static_cast<double>(alphas.size() - 1))",
     "std::sqrt(ss / static_cast<double>(alphas.size()))", R10_CALIB),
    ("r10_proximity_range_error_sqrt3", "lib/calibrate/src/proximity_fit.cpp",
     "R.std_error_m = (R.undetected_from_m - R.detected_to_m) / std::sqrt(12.0);",
     "R.std_error_m = (R.undetected_from_m - R.detected_to_m) / std::sqrt(3.0);", R10_CALIB),
    ("r10_table5_simulated_ratio_to_analytic", "lib/calibrate/src/battery_report.cpp",
     "ratio_s[std::string(mb::to_string(m))] = t.simulated.get(m) / pg.get(m);",
     "ratio_s[std::string(mb::to_string(m))] = t.simulated.get(m) / pa.get(m);", R10_CALIB),
    ("r10_format_number_sixteen_digits", "lib/logs/src/csv_writer.cpp", "for (int digits = 6; digits <= 17; ++digits) {",
     "for (int digits = 6; digits < 17; ++digits) {", R10_LOGS),
    ("r10_log_trailing_delimiter_at_header_size", LR,
     "if (cells.size() - row_first.back() == header.size() + 1 && cells.back().size == 0) cells.pop_back();",
     "if (cells.size() - row_first.back() == header.size() && cells.back().size == 0) cells.pop_back();", R10_LOGS),
    ("r10_diagnose_light_base_range_plugin", DK_LIGHT, "    range_m_ = m.base.range_m;\n",
     "    range_m_ = s::kPluginLight.range_m;\n", R10_DIAGNOSE),
    ("r10_diagnose_battery_derivative_one_step", DK_BATTERY, "out[r].v = p[k_].v * ((sim.up[i] - sim.down[i]) / (2.0 * h));",
     "out[r].v = p[k_].v * ((sim.up[i] - sim.down[i]) / h);", R10_DIAGNOSE),
    ("r10_extended_covariate_merged_by_other_column", "lib/diagnose/src/extended_model.cpp",
     "[&](const s::CovariateEffect& b) { return b.column == f.column; }",
     "[&](const s::CovariateEffect& b) { return b.column != f.column; }", R10_DIAGNOSE),
    ("r10_table5_charge_map_without_conversion", "apps/cmd_table5.cpp", "if (in.map && in.conversion.logs > 0) {", "if (in.map) {",
     R10_APPS),
    ("r10_battery_map_fitted_only_when_needed", "apps/battery_input.hpp", "} else if (fit_map || voltage_only) {",
     "} else if (fit_map && voltage_only) {", R10_APPS),
    # Session 13, before round 11's GO: probes of product files no earlier mutant touched (listed by
    # the lead, who has read the tests: they find where the tests are thin, they are no fresh round).
    ("s13_argos_capacity_time_times_k", "argos/src/calibrated_battery.cpp", "fK == 1.0 ? fDeltaT : fDeltaT / fK,",
     "fK == 1.0 ? fDeltaT : fDeltaT * fK,", R10_COEFF),
    ("s13_argos_speed_list_pair_as_range", "argos/src/calibrated_battery.cpp", 'os << (j == i + 1 ? ", " : "..") << v[j];',
     'os << (j > i ? ".." : ", ") << v[j];', R10_COEFF),
    ("s13_stale_temporary_of_a_live_run_removed", "lib/logs/src/output.cpp", "== -1 && errno == ESRCH) {",
     "== -1 || errno == ESRCH) {", R10_LOGS),
    ("s13_replaced_file_mode_not_kept", "lib/logs/src/output.cpp",
     "if (::stat(resolved.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::fchmod(",
     "if (::stat(resolved.c_str(), &st) != 0 && S_ISREG(st.st_mode) && ::fchmod(", R10_LOGS),
    ("s13_json_location_bom_not_skipped", "lib/logs/src/json_location.cpp", "? 3 : 0;", "? 0 : 0;", R10_COEFF),
    ("s13_json_location_crlf_two_lines", "lib/logs/src/json_location.cpp", "text[i + 1] != '\\n'))",
     "text[i + 1] == '\\n'))", R10_COEFF),
    ("s13_engine_covariate_every_channel", "lib/diagnose/src/engine_detail.hpp",
     "if (p_.channel[i] == 0) out[i] += values[s.param] * s.centred[i];", "out[i] += values[s.param] * s.centred[i];",
     R10_DIAGNOSE),
    ("s13_engine_covariate_mean_over_n_plus_one", "lib/diagnose/src/engine_detail.hpp",
     "mean /= std::max<std::size_t>(1, values.size());", "mean /= static_cast<double>(values.size() + 1);", R10_DIAGNOSE),
    ("s13_json_dash_is_a_file", "apps/main.cpp", 'if (value == "-") out.push_back("--json");',
     'if (value == "--") out.push_back("--json");', R10_APPS),
    ("s13_drive_figure_plugin_curve_offset", "lib/plot/src/sensor_figures.cpp", "$curves using 1:4 with lines lw 2 dt 2",
     "$curves using 1:3 with lines lw 2 dt 2", R10_APPS),
    # Round 11 (bench/fresh-slips.md): planted without reading the tests; the two lib/models headers first.
    ("r11_expected_clamp_upper_z_reversed", "lib/models/include/epuck2/models/saturation.hpp",
     "const T z = (mu - hi) / sigma;", "const T z = (hi - mu) / sigma;", R11_SATURATION),
    ("r11_drive_right_wheel_ramps_for_left_time", MD, "const T a_r = scalar_of(done) < scalar_of(tr) ? ar : T(0.0);",
     "const T a_r = scalar_of(done) < scalar_of(tl) ? ar : T(0.0);", R11_DRIVE_MODEL),
    ("r11_argos_battery_any_rotation_is_distance", "argos/src/calibrated_battery.cpp",
     "if (fDeltaPos == 0.0 && cDeltaAngle.GetValue() != 0.0) fDeltaPos", "if (cDeltaAngle.GetValue() != 0.0) fDeltaPos",
     R11_ARGOS_BATTERY),
    ("r11_argos_turn_half_difference_over_h", "argos/src/calibrated_drive.hpp",
     "((state_.xl - before.xl) - (state_.xr - before.xr)) / (2.0 * h_s);",
     "((state_.xl - before.xl) - (state_.xr - before.xr)) / h_s;", R11_ARGOS),
    ("r11_argos_wheels_do_not_apply_slip", "argos/src/applied_effects.hpp",
     "{fx::drive::speed_limit, fx::drive::accel_limit, fx::drive::wheel_slip, fx::drive::speed_scale};",
     "{fx::drive::speed_limit, fx::drive::accel_limit, fx::drive::speed_scale};", R11_ARGOS),
    ("r11_fit_curve_as_many_points_as_parameters", "lib/fit/include/epuck2/fit/fit_curve.hpp",
     "if (x.size() < static_cast<std::size_t>(Model::kParameters) + 1) {",
     "if (x.size() < static_cast<std::size_t>(Model::kParameters)) {", R11_FIT),
    ("r11_robust_replicate_judgement_from_four", RB, "group_size[groups[i]] >= kMinReplicates;",
     "group_size[groups[i]] > kMinReplicates;", R11_FIT),
    ("r11_model_path_beside_the_experiment_file_itself", "lib/coefficients/src/model_sets.cpp",
     "const fs::path beside = fs::path(experiment_file).parent_path() / p;",
     "const fs::path beside = fs::path(experiment_file) / p;", R11_COEFF),
    ("r11_battery_flat_segment_refused", "lib/coefficients/src/battery_tables.cpp", "if (!(seg.y2 <= seg.y1))",
     "if (!(seg.y2 < seg.y1))", R11_COEFF),
    ("r11_report_six_outlier_lines", "lib/calibrate/src/report_text.cpp", "i < r.outlier_where.size() && i < 5; ++i)",
     "i < r.outlier_where.size() && i <= 5; ++i)", R11_CALIB),
    ("r11_reject_sd_option_not_passed", "lib/calibrate/src/sensor_fit_common.cpp", "  r.reject_sd = o.reject_sd;\n", "",
     R11_CALIB),
    ("r11_diagnosis_base_caps_its_upper_bound", "lib/diagnose/src/kind_common.hpp", "q.upper = std::max(q.upper, v);",
     "q.upper = std::min(q.upper, v);", R11_DIAGNOSE),
    ("r11_voltage_is_a_covariate_candidate", "lib/diagnose/src/kinds.cpp",
     'add_common_covariates(*p, logs, {"angle_deg", "voltage_v"});', 'add_common_covariates(*p, logs, {"angle_deg"});',
     R11_DIAGNOSE),
    ("r11_covariate_column_in_the_last_log_only", DE, "everywhere = everywhere && log.has(name);",
     "everywhere = log.has(name);", R11_DIAGNOSE),
    ("r11_output_relative_symlink_from_cwd", "lib/logs/src/output.cpp",
     "p = link.is_absolute() ? link : p.parent_path() / link;", "p = link;", R11_LOGS),
    ("r11_drive_right_steps_read_from_left", "lib/logs/include/epuck2/logs/drive_columns.hpp",
     'log.col("left_steps"), log.col("right_steps"),', 'log.col("left_steps"), log.col("left_steps"),',
     R11_DRIVE_COLUMNS),
    ("r11_json_dash_left_as_an_argument", "apps/main.cpp", "++i;  // `--json -`: standard output, which the flag means",
     "// `--json -`: standard output, which the flag means", R11_APPS),
    ("r11_generate_out_dir_conflict_inverted", "apps/cmd_generate.cpp",
     "if (!o.out_dir.empty() && !o.old_out.empty() && o.out_dir != o.old_out)",
     "if (!o.out_dir.empty() && !o.old_out.empty() && o.out_dir == o.old_out)", R11_APPS),
    ("r11_nist_min_rss_lre_from_parameters", "apps/cmd_nist.cpp", "min_rss = std::min(min_rss, r.rss_lre);",
     "min_rss = std::min(min_rss, r.min_lre);", R11_APPS),
    ("r11_charge_map_residuals_at_rest", "lib/plot/src/charge_map_figure.cpp",
     "rows[i].charge - calibrate::convert_voltage(map, rows[i].voltage_v, rows[i].speed_cm_s).charge",
     "rows[i].charge - calibrate::convert_voltage(map, rows[i].voltage_v, 0.0).charge", R11_PLOT),
    # Round 12 (bench/fresh-slips.md): planted without reading the tests; the two lib/models headers first.
    ("r12_plugin_segment_h_and_m_swapped", "lib/models/include/epuck2/models/plugin_battery_tables.hpp",
     "t.segments[s][k] = Segment{r[0], r[1], r[2], r[3], r[4], r[5]};",
     "t.segments[s][k] = Segment{r[1], r[0], r[2], r[3], r[4], r[5]};", R12_PLUGIN_TABLES),
    ("r12_normal_spare_is_the_cosine_again", "lib/models/include/epuck2/models/noise.hpp",
     "spare_ = r * std::sin(angle);", "spare_ = r * std::cos(angle);", R12_NOISE),
    ("r12_argos_gaussian_sd_not_over_scale", "argos/src/argos_noise.hpp", "units_[i].sd_ = sd[i] / scale;",
     "units_[i].sd_ = sd[i];", R12_ARGOS),
    ("r12_argos_drive_file_steps_per_m_not_kept", "argos/src/calibrated_drive.cpp", "  c.steps_per_m = m.steps_per_m;\n", "",
     R12_ARGOS),
    ("r12_argos_encoder_right_noise_while_left_turns", AS, "bRight ? m_cNoise.level(1) : 0.0",
     "bLeft ? m_cNoise.level(1) : 0.0", R12_ARGOS),
    ("r12_generate_ground_white_rail_offset_kept", "lib/virtual_robot/src/ground.cpp",
     "gain[1] = truth.white_rail_raw - truth.offset_raw[1];", "gain[1] = truth.white_rail_raw;", R12_GENERATE),
    ("r12_generate_proximity_one_more_saturated", "lib/virtual_robot/src/proximity.cpp",
     "const bool saturated = static_cast<int>(j) < truth.saturated_distances;",
     "const bool saturated = static_cast<int>(j) <= truth.saturated_distances;", R12_GENERATE),
    ("r12_generate_camera_reflection_row_from_column", "lib/virtual_robot/src/camera.cpp",
     "if (jumped) px = wild_px, py = wild_py;", "if (jumped) px = wild_px, py = wild_px;", R12_GENERATE),
    ("r12_generate_drive_wheels_at_the_hosts_steps", "lib/virtual_robot/src/drive.cpp",
     "const double wheel_speed = rate_steps_s / true_steps_per_m;", "const double wheel_speed = rate_steps_s / truth.steps_per_m;",
     R12_GENERATE),
    ("r12_generate_battery_stop_from_the_wrong_end", "lib/virtual_robot/src/battery.cpp",
     "const double fraction = (v_prev - stop_v) / (v_prev - terminal_v);",
     "const double fraction = (stop_v - terminal_v) / (v_prev - terminal_v);", R12_GENERATE),
    ("r12_lifetime_error_bars_in_seconds", "lib/plot/src/battery_figures.cpp",
     "s.lifetime_std_error_s / 3600.0);", "s.lifetime_std_error_s);", R12_PLOT),
    ("r12_diagnosis_axis_metres_labelled_m", "lib/plot/src/diagnosis_figure.cpp", '{"_m", "mm"}', '{"_m", "m"}',
     R12_DIAGNOSIS_FIGURE),
    ("r12_battery_lifetime_figure_to_the_fits_path", "apps/cmd_battery.cpp",
     "plot::battery_lifetime_figure(stage, o.plot_lifetime, runs, f);", "plot::battery_lifetime_figure(stage, o.plot, runs, f);",
     R12_APPS),
    ("r12_robot_list_left_empty", "apps/app_support.cpp",
     "if (std::find(names.begin(), names.end(), l.robot) == names.end()) names.push_back(l.robot);",
     "if (std::find(names.begin(), names.end(), l.robot) != names.end()) names.push_back(l.robot);", R12_APPS),
    ("r12_drive_tof_misfit_judged_on_the_encoders", "apps/cmd_drive.cpp",
     'app::sensors::require_fitting(f.tof, "ToF fit", o, f.warnings);',
     'app::sensors::require_fitting(f.steps, "ToF fit", o, f.warnings);', R12_APPS),
    ("r12_log_row_default_digits_taken_as_zero", "lib/logs/src/csv_writer.cpp",
     "line += digits > 0 ? format_number(values[i], digits) : format_number(values[i]);",
     "line += digits >= 0 ? format_number(values[i], digits) : format_number(values[i]);", R12_LOGS),
    ("r12_battery_two_runs_lifetime_without_error", "lib/calibrate/src/battery_fit.cpp",  # session 21: one function
     "std::string lifetime_no_error_why(const SpeedFit& s) {\n  if (s.runs >= 2 &&",
     "std::string lifetime_no_error_why(const SpeedFit& s) {\n  if (s.runs > 2 &&", R12_CALIB),
    ("r12_bic_rss_not_over_n", "lib/fit/src/least_squares.cpp",
     "return nn * std::log(std::max(rss, std::numeric_limits<double>::min()) / nn) + k * std::log(nn);",
     "return nn * std::log(std::max(rss, std::numeric_limits<double>::min())) + k * std::log(nn);", R12_FIT),
    ("r12_battery_segment_y2_range_checks_y1", "lib/coefficients/src/battery_tables.cpp",
     'within(seg.y2, 0, 1, path, ga + "/y2", gw + ".y2", "charge");',
     'within(seg.y1, 0, 1, path, ga + "/y2", gw + ".y2", "charge");', R12_COEFF),
    ("r12_diagnosis_drive_tof_noise_channel_misnamed", "lib/diagnose/src/extended_model.cpp",
     'if (c.name == "tof_mm") tof_residual_sd = c.value;', 'if (c.name == "tof") tof_residual_sd = c.value;', R12_DIAGNOSE),
    # Round 13 (bench/fresh-slips.md): planted without reading the tests; the two lib/models headers first.
    ("r13_camera_image_rows_bounded_by_width", MC, "x <= width_px - 1.0 && y <= height_px - 1.0;",
     "x <= width_px - 1.0 && y <= width_px - 1.0;", R13_MODELS),
    ("r13_light_several_lights_gain_dropped", ML,
     "return kProximityFullScale_raw * (1.0 - e.gains.gain[static_cast<std::size_t>(sensor)] * sum) - e.ambient.offset_raw;",
     "return kProximityFullScale_raw * (1.0 - sum) - e.ambient.offset_raw;", R13_MODELS),
    ("r13_argos_ground_clamped_at_4095", AS,
     "m_tReadings[i] = static_cast<SInt32>(std::clamp(std::round(fMean), 0.0, ms::kGroundFullScale_raw));",
     "m_tReadings[i] = static_cast<SInt32>(std::clamp(std::round(fMean), 0.0, ms::kProximityFullScale_raw));", R13_ARGOS),
    ("r13_argos_capacity_distance_not_over_k", "argos/src/calibrated_battery.cpp", "fK == 1.0 ? fDeltaPos : fDeltaPos / fK,",
     "fDeltaPos,", R13_COEFF),
    ("r13_charge_map_parameters_count_first_load_speed", "lib/calibrate/include/epuck2/calibrate/charge_map.hpp",
     "knots_v.size() + (has_load() ? load_speeds_cm_s.size() - 1 : 0)",
     "knots_v.size() + (has_load() ? load_speeds_cm_s.size() : 0)", R13_BATTERY_CALIB),
    ("r13_argos_uniform_level_arguments_swapped", "lib/calibrate/include/epuck2/calibrate/reading_noise.hpp",
     "models::sensors::uniform_level_with_sd(sd, argos_scale)", "models::sensors::uniform_level_with_sd(argos_scale, sd)",
     R13_CALIB),
    ("r13_reject_sd_option_not_passed", "apps/sensor_support.hpp", "    f.reject_sd = reject_sd;\n", "", R13_APPS),
    ("r13_few_readings_two_per_parameter", "lib/fit/include/epuck2/fit/robust.hpp",
     "inline constexpr std::size_t kFewReadingsPerParameter = 3;",
     "inline constexpr std::size_t kFewReadingsPerParameter = 2;", R13_FIT),
    ("r13_identifiability_any_why_inverted", "lib/fit/include/epuck2/fit/least_squares.hpp",
     "[why](const Column& c) { return c.why == why; }", "[why](const Column& c) { return c.why != why; }", R13_FIT),
    ("r13_channel_weight_inverted", "lib/fit/include/epuck2/fit/readings.hpp",
     "Censoring::none, sd_[c], sd_[0]).value;", "Censoring::none, sd_[0], sd_[c]).value;", R13_FIT),
    ("r13_battery_table_fractional_speed_accepted", "lib/coefficients/src/battery_tables.cpp",
     "static_cast<double>(mb::kSpeedCount)) || v != std::floor(v))", "static_cast<double>(mb::kSpeedCount)))", R13_COEFF),
    ("r13_json_location_number_runs_into_brace", "lib/logs/src/json_location.cpp", 'std::string_view(",]} \\t\\r\\n")',
     'std::string_view(",] \\t\\r\\n")', R13_LOGS),
    ("r13_diagnosis_censored_count_misses_high_rail", "lib/diagnose/src/screening.cpp",
     "n += (v <= rails.low_rail || v >= rails.high_rail) ? 1 : 0;", "n += (v <= rails.low_rail || v > rails.high_rail) ? 1 : 0;",
     R13_DIAGNOSE),
    ("r13_diagnosis_r2_about_first_channels_mean", "lib/diagnose/src/search.cpp",
     "const double d = engine.error(i, sum[c] / count[c]);", "const double d = engine.error(i, sum[0] / count[0]);",
     R13_DIAGNOSE),
    ("r13_seed_largest_refused", "apps/app_support.cpp", "(digits.size() == max.size() && digits > max)",
     "(digits.size() == max.size() && digits >= max)", R13_APPS),
    ("r13_range_text_upper_bracket_from_lower", MF, '(open_hi ? ")" : "]")', '(open_lo ? ")" : "]")', R13_COEFF),
    ("r13_wild_whole_value_never_top", "lib/virtual_robot/include/epuck2/virtual_robot/sensor_truth.hpp",
     "std::floor(lo + (hi - lo + 1.0) * w)", "std::floor(lo + (hi - lo) * w)", R13_GENERATE),
    ("r13_generate_light_ambient_raises", "lib/virtual_robot/src/light.cpp", "- truth.ambient_raw + noise() * truth.noise_raw;",
     "+ truth.ambient_raw + noise() * truth.noise_raw;", R13_GENERATE),
    ("r13_generate_battery_last_speed_missing", "lib/virtual_robot/src/battery_logs.cpp",
     "for (int s = 0; s < models::battery::kSpeedCount; ++s) {", "for (int s = 0; s < models::battery::kSpeedCount - 1; ++s) {",
     R13_GENERATE),
    ("r13_battery_speed_zero_not_covered", "lib/calibrate/src/battery_fit.cpp",
     "if (centi % 100 == 0 && centi >= 0 && centi / 100 < mb::kSpeedCount)",
     "if (centi % 100 == 0 && centi > 0 && centi / 100 < mb::kSpeedCount)", R13_BATTERY_CALIB),
    # Round 14 (bench/fresh-slips.md): planted without reading the tests; the two lib/models header slips first.
    ("r14_drive_symmetric_ramp_not_cut_at_tick", MD, "    if (scalar_of(ramp) > scalar_of(h)) ramp = h;\n", "",
     R14_DRIVE_MODEL),
    ("r14_rad_to_deg_multiplies_like_deg_to_rad", "lib/models/include/epuck2/models/geometry.hpp",
     "return rad * (180.0 / kPi); }", "return rad * (kPi / 180.0); }", R14_GEOMETRY),
    ("r14_argos_tof_delay_gap_takes_farther_tick", "argos/src/calibrated_drive.hpp",
     "return (when - a.first) < (b.first - when) ? a.second : b.second;",
     "return (when - a.first) < (b.first - when) ? b.second : a.second;", R14_ARGOS),
    ("r14_argos_step_register_noise_at_zero", "argos/src/calibrated_drive.hpp",
     "const double f = count == 0.0 ? 0.0 : std::floor(count + noise_steps);",
     "const double f = std::floor(count + noise_steps);", R14_ARGOS),
    ("r14_autodiff_later_blocks_seeded_from_slot_zero", "lib/fit/include/epuck2/fit/problem.hpp",
     "x[offset + j] = J(parameters[b][j], offset + j);", "x[offset + j] = J(parameters[b][j], j);", R14_AUTODIFF),
    ("r14_wild_railed_pair_flagged", "lib/fit/src/replicates.cpp", "wild[i] = on_rail[i] ? railed == 1 && dev",
     "wild[i] = on_rail[i] ? railed >= 1 && dev", R14_FIT),
    ("r14_correlations_reported_from_0_01", "lib/fit/include/epuck2/fit/report.hpp",
     "inline constexpr double kReportedCorrelation = 0.1;", "inline constexpr double kReportedCorrelation = 0.01;", R14_FIT),
    ("r14_drive_lagged_travel_without_lag", "lib/calibrate/include/epuck2/calibrate/sensors.hpp", "  slip.tau_s = tau_s;\n", "",
     R14_CALIB),
    ("r14_quantisation_sd_is_its_variance", "lib/calibrate/src/sensor_fit_common.hpp",
     "constexpr double kQuantisationSd = 0.28867513459481287;", "constexpr double kQuantisationSd = 0.08333333333333333;",
     R14_CALIB),
    ("r14_camera_table4_left_half_dropped", "lib/calibrate/src/camera_fit.cpp",
     "if (std::abs(offset) > s::kCameraWidth_px / 4.0 && o.lateral_m != 0.0)",
     "if (offset > s::kCameraWidth_px / 4.0 && o.lateral_m != 0.0)", R14_CALIB),
    ("r14_battery_reject_at_four_sd", "lib/calibrate/include/epuck2/calibrate/battery.hpp",
     "inline constexpr double kBatteryRejectSd = 6.0;", "inline constexpr double kBatteryRejectSd = 4.0;", R14_BATTERY_CALIB),
    ("r14_diagnose_light_first_sensor_gain_free", DK_LIGHT,
     "for (std::size_t j = 1; j < seen.size(); ++j) gains.push_back(", "for (std::size_t j = 0; j < seen.size(); ++j) gains.push_back(",
     R14_DIAGNOSE),
    ("r14_implausible_noise_ratio_of_variances", "lib/diagnose/include/epuck2/diagnose/reading_noise.hpp",
     "inline constexpr double kImplausibleNoiseRatio = 2.0;", "inline constexpr double kImplausibleNoiseRatio = 4.0;",
     R14_DIAGNOSE),
    ("r14_extended_proximity_c_from_b", "lib/diagnose/src/extended_model.cpp", 'm.base.c = v.base_or("c", m.base.c);',
     'm.base.c = v.base_or("b", m.base.c);', R14_EXTENDED),
    ("r14_pooled_set_warning_lists_agreeing_parameters", "lib/coefficients/src/model_sets.cpp",
     'if (e.is_object() && e.value("exceeds_uncertainty", false) && e.contains("parameter")',
     'if (e.is_object() && e.contains("parameter")', R14_COEFF),
    ("r14_read_write_descriptor_called_read_only", "lib/logs/src/output.cpp", "if ((flags & O_ACCMODE) == O_RDONLY) return",
     "if ((flags & O_WRONLY) == 0) return", R14_LOGS),
    ("r14_ground_unusable_sensor_named_right", "apps/cmd_ground.cpp",
     '"ground sensor " + models::kind_facts("ground")->sensor_name(k);',
     '"ground sensor " + models::kind_facts("ground")->sensor_name(0);', R14_APPS),
    ("r14_proximity_means_misfit_unchecked", "apps/cmd_proximity.cpp",
     'require_fitting(f.means, "proximity fit to the means"', 'require_fitting(f.maxima, "proximity fit to the means"', R14_APPS),
    ("r14_light_help_dark_is_the_low_rail", "apps/cmd_light.cpp", 'channels.front().high_rail) + " = dark, "',
     'channels.front().low_rail) + " = dark, "', R14_APPS),
    ("r14_help_stand_in_column_names_itself", "apps/log_help.hpp", 'c + (alt.empty() ? "" : " (or " + alt + ")");',
     'c + (alt.empty() ? "" : " (or " + c + ")");', R14_APPS),
    # Round 15 (bench/fresh-slips.md): planted without reading the tests, the lib/models headers first.
    ("r15_unwrap_forward_wrap_subtracts", "lib/models/include/epuck2/models/encoders.hpp",
     "if (delta < -32768.0) delta += 65536.0;", "if (delta < -32768.0) delta -= 65536.0;", R15_MODELS),
    ("r15_proximity_mean_negative_polynomial_unclamped", "lib/models/include/epuck2/models/proximity.hpp",
     "const T poly = fmin(fmax(proximity_polynomial(abc, distance_m), T(0.0)), T(1.0));",
     "const T poly = fmin(proximity_polynomial(abc, distance_m), T(1.0));", R15_MODELS),
    ("r15_argos_cylinder_normal_axes_swapped", "argos/src/calibrated_sensors.cpp",
     "c_normal.Set(cLocal.GetX() / fRadial, cLocal.GetY() / fRadial, 0);",
     "c_normal.Set(cLocal.GetY() / fRadial, cLocal.GetX() / fRadial, 0);", R15_ARGOS),
    ("r15_argos_ground_grey_over_256", "argos/src/calibrated_sensors.cpp",
     "const double fGrey = cColor.ToGrayScale() / 255.0;", "const double fGrey = cColor.ToGrayScale() / 256.0;", R15_ARGOS),
    ("r15_wild_reading_at_six_sd", "lib/fit/include/epuck2/fit/replicates.hpp",
     "inline constexpr double kWildReadingSd = 8.0;", "inline constexpr double kWildReadingSd = 6.0;", R15_FIT),
    ("r15_wild_replicates_group_zero_unscreened", "lib/fit/src/replicates.cpp",
     "if (group[i] >= 0) groups[group[i]].push_back(i);", "if (group[i] > 0) groups[group[i]].push_back(i);", R15_FIT),
    ("r15_robot_map_pattern_matches_prefix", "lib/coefficients/src/model_sets.cpp",
     "if (*pattern == '\\0') return *text == '\\0';", "if (*pattern == '\\0') return true;", R15_COEFF),
    ("r15_proximity_means_curve_takes_maxima_c", "lib/coefficients/src/model_file.cpp",
     'm.base.c = d.base1(prefix + "c");', 'm.base.c = d.base1("c");', R15_COEFF),
    ("r15_proximity_range_undetected_from_last_detected", "lib/calibrate/src/proximity_fit.cpp",
     "R.undetected_from_m = out.points[last + 1].distance_m;", "R.undetected_from_m = out.points[last].distance_m;",
     R15_CALIB),
    ("r15_implausible_range_factor_100", "lib/calibrate/include/epuck2/calibrate/plausibility.hpp",
     "inline constexpr double kImplausibleRangeFactor = 10.0;", "inline constexpr double kImplausibleRangeFactor = 100.0;",
     R15_CALIB),
    ("r15_camera_model_cy_from_cx", "lib/calibrate/src/camera_report.cpp", 'm.base.cy_px = f.result.value("cy_px");',
     'm.base.cy_px = f.result.value("cx_px");', R15_CALIB),
    ("r15_noise_text_lists_sensors_without_readings", "lib/calibrate/src/report_text.cpp",
     "if (n.per_sensor_n[i] > 0) {", "if (n.per_sensor_n[i] >= 0) {", R15_CALIB),
    ("r15_paper_table5_cubic_and_approximated_swapped", "lib/calibrate/include/epuck2/calibrate/published.hpp",
     "return ModelMse{0.0221, 0.0170, 0.0020, 0.0025}; }", "return ModelMse{0.0221, 0.0170, 0.0025, 0.0020}; }",
     R15_BATTERY_CALIB),
    ("r15_battery_cubic_b_unit_per_s", "lib/calibrate/src/battery_report.cpp", 'parameter(s.cubic, "b", "charge/s^2", a)',
     'parameter(s.cubic, "b", "charge/s", a)', R15_BATTERY_CALIB),
    ("r15_diagnose_effect_parameters_numbered_from_1", "lib/diagnose/src/kind_common.hpp",
     'std::string(q.key) + "[" + std::to_string(k) + "]";', 'std::string(q.key) + "[" + std::to_string(k + 1) + "]";',
     R15_DIAGNOSE),
    ("r15_tof_in_view_margin_one_percent", "lib/diagnose/src/screening.hpp",
     "inline constexpr double kTofInViewMargin = 0.1;", "inline constexpr double kTofInViewMargin = 0.01;", R15_DIAGNOSE),
    ("r15_json_pointer_tilde_escapes_swapped", "lib/logs/src/json_location.cpp",
     "token += raw[k + 1] == '0' ? '~' : '/';", "token += raw[k + 1] == '1' ? '~' : '/';", R15_LOGS),
    ("r15_standard_output_file_not_alone", "apps/sensor_support.hpp",
     "  if (logs::is_standard_output(o.output)) return 0;  // -o -: the file is standard output, alone\n", "", R15_APPS),
    ("r15_camera_help_lateral_to_the_right", "apps/cmd_camera.cpp", 'lateral_m > 0 to the left."',
     'lateral_m > 0 to the right."', R15_APPS),
    ("r15_codegen_inputs_unchecked", "apps/cmd_codegen.cpp", "->required()->check(CLI::ExistingFile);", "->required();",
     R15_APPS),
    # Round 16 (bench/fresh-slips.md): planted without reading the tests, mostly in files no round slipped.
    ("r16_log_covariate_from_three_logs", "lib/diagnose/src/engine.cpp",
     'if (logs.size() > 1) p.add_row_covariate("log", std::move(which));',
     'if (logs.size() > 2) p.add_row_covariate("log", std::move(which));', R16_DIAGNOSE),
    ("r16_per_sensor_noise_all_first_sensor", "lib/calibrate/include/epuck2/calibrate/report_json.hpp",
     "? c.per_sensor_sd[i] : c.sd;", "? c.per_sensor_sd[0] : c.sd;", R16_CALIB),
    ("r16_drive_firmware_cap_bic_uncapped_is_capped", "lib/calibrate/src/drive_report.cpp",
     'j["firmware_cap"]["bic_uncapped"] = f.bic_uncapped;', 'j["firmware_cap"]["bic_uncapped"] = f.bic_capped;', R16_CALIB),
    ("r16_fit_upper_bound_checked_on_lower", "lib/fit/src/fit_curve.cpp",
     "if (std::isfinite(parameters[j].upper)) problem.set_upper_bound(",
     "if (std::isfinite(parameters[j].lower)) problem.set_upper_bound(", R16_FIT),
    ("r16_coefficient_cache_ignores_modification_time", "lib/coefficients/src/model_sets.cpp",
     "it->second.size == size && it->second.modified == modified", "it->second.size == size", R16_COEFF),
    ("r16_argos_gaussian_noise_level_half", "argos/src/argos_noise.hpp", "levels_[i] = 1.0;", "levels_[i] = 0.5;",
     R16_ARGOS),
    ("r16_log_writer_rows_numbered_from_0", "lib/logs/src/csv_writer.cpp",
     'throw std::domain_error("row " + std::to_string(rows_.size() + 1)',
     'throw std::domain_error("row " + std::to_string(rows_.size())', R16_LOGS),
    ("r16_closed_stdout_called_descriptor_1", "lib/logs/src/output.cpp",
     "const std::string which = t.descriptor == STDOUT_FILENO ?", "const std::string which = t.descriptor == STDERR_FILENO ?",
     R16_LOGS),
    ("r16_nist_order_reversed", "apps/cmd_nist.cpp", "return rank(a) != rank(b) ? rank(a) < rank(b) : a < b;",
     "return rank(a) != rank(b) ? rank(a) > rank(b) : a < b;", R16_APPS),
    ("r16_did_you_mean_half_of_shorter_word", "apps/app_support.cpp",
     "if (d < best_distance && 2 * d < std::max(w.size(), c.size())) {",
     "if (d < best_distance && 2 * d < std::min(w.size(), c.size())) {", R16_APPS),
    # Round 17 (bench/fresh-slips.md): planted without reading the tests; the lib/models header first.
    ("r17_camera_aperture_over_height", MC, "return std::atan(std::tan(hfov_rad / 2.0) * std::sqrt(w * w + h * h) / w);",
     "return std::atan(std::tan(hfov_rad / 2.0) * std::sqrt(w * w + h * h) / h);", R17_MODELS),
    ("r17_argos_camera_box_abs_dropped", AS, "const CVector3 cHalf(Abs(cCorner.GetX()) + fHalfSide,",
     "const CVector3 cHalf(cCorner.GetX() + fHalfSide,", R17_ARGOS),
    ("r17_argos_ground_offset_not_rotated", AS, "    cSensorPos.Rotate(cRotZ);\n", "", R17_ARGOS),
    ("r17_free_parameters_more_starts_accepted", "lib/fit/include/epuck2/fit/parameter.hpp",
     "if (names.size() != starts.size())", "if (names.size() > starts.size())", R17_FIT),
    ("r17_readings_block_channel_length_unchecked", "lib/fit/src/problem.cpp",
     "if (static_cast<std::size_t>(latent.residuals) != readings.size() || (!channel.empty() && channel.size() != readings.size()))",
     "if (static_cast<std::size_t>(latent.residuals) != readings.size())", R17_FIT),
    ("r17_linear_start_moves_fixed_first_parameter", "lib/fit/include/epuck2/fit/fit_curve.hpp",
     "if (j >= 0 && j < P) free_column[static_cast<std::size_t>(j)] = false;",
     "if (j > 0 && j < P) free_column[static_cast<std::size_t>(j)] = false;", R17_FIT),
    ("r17_refused_robot_set_left_in_file", MF, '    else j.erase("robots");\n', "", R17_COEFF),
    ("r17_light_per_sensor_fractional_number", MF,
     "if (!(k >= 0 && k < static_cast<double>(s::kProximityCount)) || k != std::floor(k))",
     "if (!(k >= 0 && k < static_cast<double>(s::kProximityCount)))", R17_COEFF),
    ("r17_battery_key_hint_two_edits_only", "lib/coefficients/src/battery_tables.cpp",
     "std::size_t best_d = std::max<std::size_t>(2, it.key().size() / 3) + 1;",
     "std::size_t best_d = std::min<std::size_t>(2, it.key().size() / 3) + 1;", R17_COEFF),
    ("r17_report_method_censoring_kept_without_rails", "lib/calibrate/src/report_text.cpp",
     "!has_rails && at != std::string::npos) method.erase(", "has_rails && at != std::string::npos) method.erase(", R17_CALIB),
    ("r17_noise_text_groups_when_not_replicates", "lib/calibrate/src/report_text.cpp",
     'if (n.from == "replicates") out(" in %zu groups", n.groups);',
     'if (n.from != "replicates") out(" in %zu groups", n.groups);', R17_CALIB),
    ("r17_proximity_range_farthest_distance_unchecked", "lib/calibrate/src/proximity_fit.cpp",
     "for (std::size_t i = 0; i < out.points.size(); ++i)\n      if (detected(out.points[i].distance_m)) last = i;",
     "for (std::size_t i = 0; i + 1 < out.points.size(); ++i)\n      if (detected(out.points[i].distance_m)) last = i;",
     R17_CALIB),
    ("r17_diagnose_camera_image_row_is_column", DK_CAMERA, "image_row.push_back(nominal_row);",
     "image_row.push_back(nominal_column);", R17_DIAGNOSE),
    ("r17_drive_spike_on_command_change_dropped", SC, "if (!(std::abs(d[i]) > limit) || !repeats(i)) continue;",
     "if (!(std::abs(d[i]) > limit)) continue;", R17_DIAGNOSE),
    ("r17_drive_spike_message_right_neighbour_is_left", SC, '" and " + logs::format_number(y[i + 1], 6) +',
     '" and " + logs::format_number(y[i - 1], 6) +', R17_DIAGNOSE),
    ("r17_log_crlf_two_line_ends", LR, "if (s[i] == '\\r' && i + 1 < s.size() && s[i + 1] == '\\n') ++i;",
     "if (s[i] == '\\r' && i + 1 < s.size() && s[i + 1] == '\\r') ++i;", R17_LOGS),
    ("r17_log_space_escaped", LR, "if ((c < 0x20 && c != '\\t') || c == 0x7f) {",
     "if ((c <= 0x20 && c != '\\t') || c == 0x7f) {", R17_LOGS),
    ("r17_like_first_unseen_is_second", "apps/cmd_simulate_like.cpp", "if (simulated[i].empty() && unseen++ == 0) first_unseen = i;",
     "if (simulated[i].empty() && unseen++ == 1) first_unseen = i;", R17_APPS),
    ("r17_like_seed_key_capitalised", "apps/cmd_simulate_like.cpp", 'if (k != "seed") w.metadata(k, v);',
     'if (k != "Seed") w.metadata(k, v);', R17_APPS),
    ("r17_skipped_rows_first_10_at_exactly_10", "apps/app_support.cpp", '(total > 10 ? ", the first 10:" : ":")',
     '(total >= 10 ? ", the first 10:" : ":")', R17_APPS),
    # Round 18 (bench/fresh-slips.md): planted without reading the tests; the lib/models header first.
    ("r18_expected_clamp_far_above_is_low_clamp", "lib/models/include/epuck2/models/saturation.hpp",
     "if (m - hi > kFar * sigma && m - lo > kFar * sigma) return T(hi);",
     "if (m - hi > kFar * sigma && m - lo > kFar * sigma) return T(lo);", R18_MODELS),
    ("r18_argos_firmware_cap_from_plugin_steps", "argos/src/calibrated_drive.cpp",
     "c.effects.speed_limit.max_cm_s = firmware_cap_cm_s(c.steps_per_m);",
     "c.effects.speed_limit.max_cm_s = firmware_cap_cm_s(ms::kPluginStepsPerMetre);", R18_ARGOS),
    ("r18_argos_light_sensor_gain_not_applied", "argos/src/applied_effects.hpp",
     "static const Applied a{fx::light::ambient_offset, fx::light::falloff_exponent, fx::light::sensor_gain};",
     "static const Applied a{fx::light::ambient_offset, fx::light::falloff_exponent};", R18_ARGOS),
    ("r18_wild_replicates_three_readings_unscreened", "lib/fit/src/replicates.cpp",
     "if (members.size() < kMinReplicates) continue;", "if (members.size() <= kMinReplicates) continue;", R18_FIT),
    ("r18_channels_noise_sd_count_unchecked", "lib/fit/src/readings.cpp",
     '  if (sd.size() != channels_.size()) throw std::invalid_argument("fit::Channels: one noise sd per channel");\n', "", R18_FIT),
    ("r18_fit_one_sided_bound_not_bounded", "lib/fit/include/epuck2/fit/fit_curve.hpp",
     "(std::isfinite(parameters[j].lower) || std::isfinite(parameters[j].upper))",
     "(std::isfinite(parameters[j].lower) && std::isfinite(parameters[j].upper))", R18_FIT),
    ("r18_robot_set_noise_section_missed", "lib/coefficients/src/model_sets.cpp",
     'if (robot.empty() || !root.contains("robots") || !root.at("robots").is_object() || !root.at("robots").contains(robot))',
     'if (!robot.empty() || !root.contains("robots") || !root.at("robots").is_object() || !root.at("robots").contains(robot))', R18_COEFF),
    ("r18_robot_map_empty_robot_id_accepted", "lib/coefficients/src/model_sets.cpp",
     "if (colon == std::string::npos || colon == 0 || colon + 1 == item.size())",
     "if (colon == std::string::npos || colon == 0)", R18_COEFF),
    ("r18_model_path_in_working_folder_not_found", "lib/coefficients/src/model_sets.cpp",
     "  if (fs::exists(p, ec)) return name;\n", "", R18_COEFF),
    ("r18_camera_aperture_why_when_finite", "lib/calibrate/src/camera_report.cpp",
     'if (!std::isfinite(f.result.std_error("fov_deg"))) j["std_error_why"]["aperture_deg"] = "follows fov_deg";',
     'if (std::isfinite(f.result.std_error("fov_deg"))) j["std_error_why"]["aperture_deg"] = "follows fov_deg";', R18_CALIB),
    ("r18_light_text_rails_swapped", "lib/calibrate/src/light_report.cpp",
     "f.readings, f.observations.size(), f.censored, light.low_rail, light.high_rail, f.left_out.size());",
     "f.readings, f.observations.size(), f.censored, light.high_rail, light.low_rail, f.left_out.size());", R18_CALIB),
    ("r18_proximity_text_six_wild_readings_shown", "lib/calibrate/src/proximity_report.cpp",
     'if (l.why.rfind("wild", 0) == 0 && shown++ < 5) out(', 'if (l.why.rfind("wild", 0) == 0 && shown++ <= 5) out(', R18_CALIB),
    ("r18_diagnose_light_last_sensor_ratio_kept_at_1", "lib/diagnose/src/kind_light.cpp",
     "for (std::size_t k = 0; k < ratio_.size(); ++k) ratio_[k] = s::light_gamma_ratio(m, static_cast<int>(k));",
     "for (std::size_t k = 0; k + 1 < ratio_.size(); ++k) ratio_[k] = s::light_gamma_ratio(m, static_cast<int>(k));", R18_DIAGNOSE),
    ("r18_diagnose_extra_columns_skip_list_inverted", "lib/diagnose/src/engine.cpp",
     "if (std::find(skip.begin(), skip.end(), c) == skip.end()) extras.insert(c);",
     "if (std::find(skip.begin(), skip.end(), c) != skip.end()) extras.insert(c);", R18_DIAGNOSE),
    ("r18_extended_column_mean_over_logs", "lib/diagnose/src/extended_model.cpp",
     "if (everywhere && n > 0) in.column_means[name] = sum / static_cast<double>(n);",
     "if (everywhere && n > 0) in.column_means[name] = sum / static_cast<double>(logs.size());", R18_DIAGNOSE),
    ("r18_log_writer_last_column_named_by_number", "lib/logs/src/csv_writer.cpp",
     "(i < columns_.size() ? columns_[i] : std::to_string(i + 1))",
     "(i + 1 < columns_.size() ? columns_[i] : std::to_string(i + 1))", R18_LOGS),
    ("r18_log_later_time_error_reported_first", "lib/logs/src/log.cpp",
     "before(*time_problem, *first)", "before(*first, *time_problem)", R18_LOGS),
    ("r18_generate_relative_new_out_dir_refused", "apps/cmd_generate.cpp",
     '    if (existing.empty()) existing = ".";\n', "", R18_APPS),
    ("r18_battery_input_voltage_only_never_seen", "apps/battery_input.hpp",
     'voltage_only = voltage_only || !l.has("charge");', 'voltage_only = voltage_only && !l.has("charge");', R18_APPS),
    ("r18_table5_one_speed_plural", "apps/cmd_table5.cpp",
     '(c.covered.size() == 1 ? " speed: " : " speeds: ")', '(c.covered.size() == 0 ? " speed: " : " speeds: ")', R18_APPS),
    # Round 19 (bench/fresh-slips.md): planted without reading the tests; the lib/models header first.
    ("r19_proximity_incidence_beyond_90_deg_zero_without_effect", "lib/models/include/epuck2/models/proximity.hpp",
     "if (!(cos_incidence > 0)) return e.k == T(0.0) ? T(1.0) : T(0.0);", "if (!(cos_incidence > 0)) return T(0.0);", R19_MODELS),
    ("r19_argos_battery_model_approx_alias_refused", "argos/src/calibrated_battery.cpp",
     '    if (strModel == "approx") strModel = "approximated";\n', "", R19_COEFF),
    ("r19_argos_actuator_reset_keeps_drive", "argos/src/calibrated_actuator.cpp",
     "    if (m_pcDrive) m_pcDrive->reset();\n", "", R19_ARGOS),
    # Session 21: ARGoS's Reset, tested by argos_calibrated_reset (an experiment run, reset, run again).
    ("s21_argos_actuator_reset_keeps_command", "argos/src/calibrated_actuator.cpp",
     "    m_fCommand[0] = m_fCommand[1] = 0.0;\n", "", R19_ARGOS),
    ("s21_argos_tof_reset_keeps_delay_line", "argos/src/calibrated_sensors.cpp",
     "  m_cDelay.reset();\n  m_fTime = 0;\n", "  m_fTime = 0;\n", R19_ARGOS),
    ("s21_argos_encoder_reset_keeps_travel", "argos/src/calibrated_sensors.cpp",
     "  m_fLeftTravel = m_fRightTravel = 0;\n", "", R19_ARGOS),
    ("s21_argos_battery_no_restart_on_clock", "argos/src/calibrated_battery.cpp",
     "    if (m_bRan && unClock <= m_unLastClock) Restart();\n", "", R19_ARGOS),
    ("s21_argos_battery_restart_keeps_pose", "argos/src/calibrated_battery.cpp",
     "    m_cOldPosition = m_cStartPosition;\n", "", R19_ARGOS),
    ("r19_information_criteria_no_residual_inverted", "lib/fit/src/report.cpp",
     '(s.n == 0 ? "no residual" : kInformationCriteriaUndefined)', '(s.n != 0 ? "no residual" : kInformationCriteriaUndefined)',
     R19_FIT),
    ("r19_fixed_value_decimals_beside_error_of_tens", "lib/fit/src/report.cpp",
     'v = printf_string("%.*f", t.last < 0 ? -t.last : 0, rounded);', 'v = printf_string("%.*f", -t.last, rounded);', R19_FIT),
    ("r19_pretty_unit_cube_left_as_caret", "lib/fit/src/report.cpp",
     "(unit[i + 1] == '2' || unit[i + 1] == '3')", "unit[i + 1] == '2'", R19_FIT),
    ("r19_robot_read_skips_pooled_set_check", "lib/coefficients/src/model_file.cpp",
     "    if (!robot.empty()) read(std::string());\n", "", R19_COEFF),
    ("r19_zero_std_error_refused", "lib/coefficients/src/model_file.cpp",
     'if (!(x >= 0)) fail(pointer, "std_errors." + key', 'if (!(x > 0)) fail(pointer, "std_errors." + key', R19_COEFF),
    ("r19_partial_battery_table_at_its_index", "lib/coefficients/src/battery_tables.cpp",
     "read_speed(speeds.at(i), static_cast<std::size_t>(s), i, path, t);",
     "read_speed(speeds.at(i), i, static_cast<std::size_t>(s), path, t);", R19_COEFF),
    ("r19_battery_lifetime_two_runs_called_one", "lib/calibrate/src/battery_fit.cpp",  # session 21: one function
     'return s.runs < 2 ? "the end of the only run\'s log', 'return s.runs <= 2 ? "the end of the only run\'s log', R19_CALIB),
    ("r19_charge_conversion_above_is_below", "lib/calibrate/src/battery_report.cpp",
     '{"clamped_above_range", c.above_range},', '{"clamped_above_range", c.below_range},', R19_CALIB),
    ("r19_sensor_robot_index_every_log_a_robot", "lib/calibrate/src/sensor_fit_common.cpp",
     "  if (named != names.end()) return static_cast<int>(named - names.begin());\n", "", R19_CALIB),
    ("r19_diagnose_battery_one_row_log_not_compared", "lib/diagnose/src/kind_battery.cpp",
     "if (i + 1 < log.rows() || log.rows() == 1) {", "if (i + 1 < log.rows()) {", R19_DIAGNOSE),
    ("r19_diagnose_base_kind_refusal_names_base_twice", "lib/diagnose/src/kinds.cpp",
     '", the logs of the kind " + std::string(logs::to_string(kind));',
     '", the logs of the kind " + std::string(logs::to_string(base_model_kind(options.base_model)));', R19_DIAGNOSE),
    ("r19_diagnose_camera_base_distortion_ignored", "lib/diagnose/src/kind_camera.cpp",
     "    set_base_effects(*this, ix_, m.distortion);\n", "", R19_DIAGNOSE),
    ("r19_json_overflow_negative_one_column_late", "lib/logs/src/json_location.cpp",
     "if (c != '-' && (c < '0' || c > '9')) continue;", "if (c < '0' || c > '9') continue;", R19_LOGS),
    ("r19_log_last_line_without_line_end_dropped", "lib/logs/src/log.cpp",
     "  if (start < s.size()) lines.push_back(s.substr(start));\n", "", R19_LOGS),
    ("r19_diagnose_file_discharge_model_only_when_cli_gives_one", "apps/cmd_diagnose.cpp",
     'file.contains("battery_model") && o.battery_model_given == 0',
     'file.contains("battery_model") && o.battery_model_given != 0', R19_APPS),
    ("r19_sensor_misfit_refused_only_with_accept", "apps/sensor_support.cpp",
     "if (!o.accept_misfit)", "if (o.accept_misfit)", R19_APPS),
    ("r19_battery_charge_map_from_file_inverted", "apps/cmd_battery.cpp",
     'if (!in.map_from_file.empty()) j["charge_map"]["from_file"] = in.map_from_file;',
     'if (in.map_from_file.empty()) j["charge_map"]["from_file"] = in.map_from_file;', R19_APPS),
    # Round 20 (bench/fresh-slips.md): planted without reading the tests; the lib/models header first.
    ('r20_saturate_low_clamp_only_with_a_high_one', 'lib/models/include/epuck2/models/saturation.hpp',
     '  if (std::isfinite(lo)) out = fmax(out, T(lo));', '  if (std::isfinite(hi)) out = fmax(out, T(lo));', R20_MODELS),
    ('r20_argos_battery_plugin_tables_need_a_file', 'argos/src/calibrated_battery.cpp',
     'if (strFile.empty() && strTables == "file")', 'if (strFile.empty())', R20_COEFF),
    ('r20_argos_cylinder_side_hit_given_cap_normal', 'argos/src/calibrated_sensors.cpp',
     'if (fHalfHeight - Abs(fZ) < pcCylinder->GetRadius() - fRadial || !(fRadial > 0)) {', 'if (fHalfHeight - Abs(fZ) > pcCylinder->GetRadius() - fRadial || !(fRadial > 0)) {', R20_ARGOS),
    ('r20_exactly_determined_fit_error_reason_lost', 'lib/fit/src/least_squares.cpp',
     'else if (n <= cols.size())', 'else if (n < cols.size())', R20_FIT),
    ('r20_lower_bound_called_upper', 'lib/fit/src/fit_curve.cpp',
     'at_bound.emplace_back(static_cast<int>(j), "lower");', 'at_bound.emplace_back(static_cast<int>(j), "upper");', R20_FIT),
    ('r20_channel_reading_below_rail_taken_at_top', 'lib/fit/src/readings.cpp',
     'censoring == Censoring::at_or_below ? ch.rail_lo :', 'censoring == Censoring::at_or_below ? ch.rail_hi :', R20_FIT),
    ('r20_partial_battery_file_without_speeds_read', 'lib/coefficients/src/battery_tables.cpp',
     'if (speeds.empty() || speeds.size() > mb::kSpeedCount)', 'if (speeds.size() > mb::kSpeedCount)', R20_COEFF),
    ('r20_codegen_calibration_sources_not_named', 'lib/coefficients/src/codegen.cpp',
     'j.contains("sources") ? "sources" : "logs"', 'j.contains("sources") ? "logs" : "sources"', R20_COEFF),
    ('r20_null_noise_section_counted', 'lib/coefficients/src/model_sets.cpp',
     'if (root.contains("noise") && !root.at("noise").is_null()) return true;', 'if (root.contains("noise")) return true;', R20_COEFF),
    ('r20_proximity_distance_at_range_left_out', 'lib/calibrate/src/proximity_fit.cpp',
     '    if (d > start.range_m) {', '    if (d >= start.range_m) {', R20_CALIB),
    ('r20_light_plugin_mse_counts_zero_readings', 'lib/calibrate/src/light_fit.cpp',
     'if (o.value_raw > 0 && o.value_raw < s::kProximityFullScale_raw)', 'if (o.value_raw >= 0 && o.value_raw < s::kProximityFullScale_raw)', R20_CALIB),
    ('r20_camera_two_observations_refused', 'lib/calibrate/src/camera_fit.cpp',
     'if (out.observations.size() < 2) {', 'if (out.observations.size() < 3) {', R20_CALIB),
    ('r20_diagnose_proximity_one_tilted_angle_drops_incidence', 'lib/diagnose/src/kind_proximity.cpp',
     'angles_vary = angles_vary || std::abs(v - cos_.front()) > 1e-9 || v < 1.0 - 1e-12;', 'angles_vary = angles_vary || std::abs(v - cos_.front()) > 1e-9;', R20_DIAGNOSE),
    ('r20_diagnose_single_channel_noise_never_warned', 'lib/diagnose/src/reading_noise.cpp',
     '  if (residual.empty()) residual.push_back({"", r.noise_sd, 0.0});\n', '', R20_DIAGNOSE),
    ('r20_diagnose_tail_rows_at_range_counted_beyond', 'lib/diagnose/src/kind_proximity.cpp',
     'if (distance_[i] <= range_m_) {', 'if (distance_[i] < range_m_) {', R20_DIAGNOSE),
    ('r20_output_dev_stderr_is_standard_output', 'lib/logs/src/output.cpp',
     'else if (path == "/dev/stderr") fd = STDERR_FILENO;', 'else if (path == "/dev/stderr") fd = STDOUT_FILENO;', R20_LOGS),
    ('r20_output_proc_self_fd_number_one_early', 'lib/logs/src/output.cpp',
     'fd = descriptor_number(path.substr(14));', 'fd = descriptor_number(path.substr(13));', R20_LOGS),
    ('r20_like_one_text_column_not_said', 'apps/cmd_simulate_like.cpp',
     'if (text_columns > 0)', 'if (text_columns > 1)', R20_APPS),
    ('r20_table5_other_speeds_clause_inverted', 'apps/cmd_table5.cpp',
     'if (!c.other.empty()) why +=', 'if (c.other.empty()) why +=', R20_APPS),
    ('r20_finite_range_accepts_nan', 'apps/app_support.cpp',
     'if (!std::isfinite(v) || v < lo || v > hi)', 'if (v < lo || v > hi)', R20_APPS),
    # Round 21 (bench/fresh-slips.md): its 8 survivors and its one kill by a byte-for-byte comparison
    # only, written again from the round's record (the round's branch, with its 20 mutants, was lost
    # with the machine it ran on; its 11 correctness kills are not here).
    ('r21_argos_robot_set_noise_channel_warned_missing', 'argos/src/calibrated_sensors.cpp',
     'if (!HasChannel(*s.Root) && !(pcRobotSet && HasChannel(*pcRobotSet)))', 'if (!HasChannel(*s.Root))', R20_ARGOS),
    ('r21_battery_zero_slope_refused_as_rising', 'lib/coefficients/src/battery_tables.cpp',
     'if (sign == Sign::negative_or_zero && !(v <= 0))', 'if (sign == Sign::negative_or_zero && !(v < 0))', R20_COEFF),
    ('r21_battery_static_slope_left_zero_without_a_run_at_rest', 'lib/calibrate/src/battery_fit.cpp',
     '  if (out.simple_static_slope_per_s == 0) out.simple_static_slope_per_s = out.simple_moving_slope_per_s;\n', '', R20_CALIB),
    ('r21_corrected_error_shown_when_equal', 'lib/calibrate/src/report_text.cpp',
     'autocorrelation->std_error(name) > e)', 'autocorrelation->std_error(name) >= e)', R20_CALIB),
    ('r21_diagnose_unit_of_a_base_key_with_its_unit_lost', 'lib/diagnose/src/report_output.cpp',
     'if (base == p.key || base == std::string(p.key) + "_" + p.unit) return p.unit;', 'if (base == p.key) return p.unit;', R20_DIAGNOSE),
    ('r21_diagnose_battery_start_charge_sides_swapped', 'lib/diagnose/src/kind_battery.cpp',
     'r.start_charge = c.front() >= s::kBatteryStartsFull ? 1.0 : c.front();', 'r.start_charge = c.front() >= s::kBatteryStartsFull ? c.front() : 1.0;', R20_DIAGNOSE),
    ('r21_diagnose_autocorrelation_smallest_channel_taken', 'lib/diagnose/src/search.cpp',
     'if (a.computed && (!best.computed || a.factor > best.factor)) {', 'if (a.computed && (!best.computed || a.factor < best.factor)) {', R20_DIAGNOSE),
    ('r21_log_empty_robot_metadata_taken', 'lib/logs/src/log.cpp',
     'it != log.metadata.end() && !it->second.empty()) {', 'it != log.metadata.end()) {', R20_LOGS),
    ('r21_lack_of_fit_worst_run_spans_the_other_side', 'lib/fit/src/robust.cpp',
     'return std::abs(miss[i]) >= 0.5 * std::abs(miss[top]) && (miss[i] > 0) == (miss[top] > 0);', 'return std::abs(miss[i]) >= 0.5 * std::abs(miss[top]);', R20_FIT),
    # Session 24: a pooled fit's wild-reading screen groups replicates within a robot (probe 5, 02).
    ('s24_wild_screen_groups_span_robots', 'lib/fit/src/robust.cpp',
     'screen_group.emplace(std::make_pair(obs[i].group, obs[i].robot),', 'screen_group.emplace(std::make_pair(obs[i].group, -1),', R20_FIT),
    ('s24_proximity_wild_screen_groups_span_robots', 'lib/calibrate/src/proximity_fit.cpp',
     'group_of.emplace(std::make_pair(d, r.robot),', 'group_of.emplace(std::make_pair(d, -1),', R20_CALIB),
    ('s24_diagnose_sensor_noise_capped_at_pooled_residuals', 'lib/diagnose/src/reading_noise.cpp',
     '      sd = n.per_sensor_sd[k] * cap;', '      sd = std::min(n.per_sensor_sd[k], residual_sd);', R20_DIAGNOSE),
    ('s24_camera_subpixel_log_rounded', 'lib/models/include/epuck2/models/simulate_log.hpp',
     '    if (noise && subpixel) {', '    if (noise && subpixel && false) {', R20_MODELS),
    ('s24_diagnose_dropouts_counted_on_rails', 'lib/diagnose/src/search.cpp',
     '    report_.censored -= std::min(report_.censored, problem_->left_out_on_rails.size());\n', '', R20_DIAGNOSE),
    ('s24_drive_slip_lag_below_range_written', 'lib/calibrate/src/drive_report.cpp',
     '    if (fx::between_neutral_and_range(q, v)) v = q.neutral;\n', '', R20_CALIB),
    ('s24_lack_of_fit_robots_not_counted', 'lib/fit/src/robust.cpp',
     '            if (obs[i].robot >= 0) spanned.insert(obs[i].robot);\n', '', R20_FIT),
    # Round 22 (bench/fresh-slips.md): planted without reading the tests; the lib/models header first.
    ('r22_tof_reading_floored_not_rounded', 'lib/models/include/epuck2/models/tof.hpp',
     'std::clamp(std::round(reading_m * 1000.0), k.min_mm, k.max_mm)', 'std::clamp(std::floor(reading_m * 1000.0), k.min_mm, k.max_mm)', R20_MODELS),
    ('r22_argos_tof_delay_weight_on_wrong_side', 'argos/src/calibrated_drive.hpp',
     'const double w = (when - a.first) / (b.first - a.first);', 'const double w = (b.first - when) / (b.first - a.first);', R20_ARGOS),
    ('r22_argos_camera_image_width_height_swapped', 'argos/src/calibrated_sensors.cpp',
     'camera_image_holds(fX, fY, m_cCam.GetImagePxWidth(), m_cCam.GetImagePxHeight())', 'camera_image_holds(fX, fY, m_cCam.GetImagePxHeight(), m_cCam.GetImagePxWidth())', R20_ARGOS),
    ('r22_correlation_over_first_variance_twice', 'lib/fit/src/report.cpp',
     'std::clamp(c(i, j) / std::sqrt(vi * vj), -1.0, 1.0)', 'std::clamp(c(i, j) / std::sqrt(vi * vi), -1.0, 1.0)', R20_FIT),
    ('r22_error_of_a_millionth_not_fixed', 'lib/fit/src/report.cpp',
     'return t.last >= kLowestFixedDigit ||', 'return t.last > kLowestFixedDigit ||', R20_FIT),
    ('r22_wild_reading_centre_is_the_reading', 'lib/fit/src/replicates.cpp',
     'centre on " + logs::format_number(med, 6)', 'centre on " + logs::format_number(values[i], 6)', R20_FIT),
    ('r22_robot_map_with_a_robot_id_accepted', 'lib/coefficients/src/model_sets.cpp',
     'if (!robot_map.empty() && attribute != "auto")', 'if (!robot_map.empty() && attribute.empty())', R20_COEFF),
    ('r22_drive_refuted_firmware_cap_applied', 'lib/coefficients/src/model_file.cpp',
     ' && j.at("firmware_cap").is_object() && !firmware_cap_refuted(j);', ' && j.at("firmware_cap").is_object();', R20_COEFF),
    ('r22_codegen_two_files_of_one_kind_accepted', 'lib/coefficients/src/codegen.cpp',
     'if (!fresh) refuse(in, "/kind", "a second coefficient file', 'if (!fresh && first->second == in) refuse(in, "/kind", "a second coefficient file', R20_COEFF),
    ('r22_battery_lifetime_mean_of_rows_not_runs', 'lib/calibrate/src/battery_json.cpp',
     '" (mean of " + std::to_string(s.runs) +', '" (mean of " + std::to_string(s.observations) +', R20_CALIB),
    ('r22_ground_observations_last_sensor_only', 'lib/calibrate/src/ground_report.cpp',
     '    observations += r.observations;', '    observations = r.observations;', R20_CALIB),
    ('r22_battery_text_least_squares_called_rejecting', 'lib/calibrate/src/battery_report.cpp',
     '  if (reject_sd > 0)\n    out("Readings left out', '  if (reject_sd >= 0)\n    out("Readings left out', R20_CALIB),
    ('r22_extended_ground_sensor_offset_dropped', 'lib/diagnose/src/extended_model.cpp',
     'm.sensors[k].offset_raw + black};', 'm.sensors[k].offset_raw + offset};', R20_DIAGNOSE),
    ('r22_extended_model_base_sides_swapped', 'lib/diagnose/src/extended_model.cpp',
     'r.final_base.empty() ? r.recalibrated : r.final_base', 'r.final_base.empty() ? r.final_base : r.recalibrated', R20_DIAGNOSE),
    ('r22_diagnose_spike_limit_below_the_floor', 'lib/diagnose/src/screening.cpp',
     'std::max(fit::kWildReadingSd * sd, facts.screening.floor)', 'std::min(fit::kWildReadingSd * sd, facts.screening.floor)', R20_DIAGNOSE),
    ('r22_json_pointer_first_token_empty', 'lib/logs/src/json_location.cpp',
     "std::size_t start = 1;  // after the leading '/'", "std::size_t start = 0;  // after the leading '/'", R20_LOGS),
    ('r22_log_short_row_column_one_early', 'lib/logs/src/log.cpp',
     ': raw_length[i] + 1;', ': raw_length[i];', R20_LOGS),
    ('r22_diagnose_output_file_empty_without_json', 'apps/cmd_diagnose.cpp',
     'o.json || !output.empty() ? json_text(', 'o.json && !output.empty() ? json_text(', R20_APPS),
    ('r22_simulate_charge_six_digits', 'apps/cmd_simulate.cpp',
     '"%.10g,%.17g\\n"', '"%.10g,%.6g\\n"', R20_APPS),
    ('r22_robots_logged_count_without_set_left_out', 'apps/sensor_support.cpp',
     'std::printf("\\nRobots (%zu logged):\\n%s", usable + without, lines.c_str());', 'std::printf("\\nRobots (%zu logged):\\n%s", usable, lines.c_str());', R20_APPS),
]


def sh(cmd, **kw):
    return subprocess.run(cmd, cwd=kw.pop("cwd", ROOT), **kw)


def copy_source():
    """Copies the checkout (without build folders, .git and the fuzz corpus) into SRC, keeping
    SRC/build and its objects. The copies get the time of the copy, not the checkout's: a source
    older than an object of an earlier run (a mutant's restore touched that object later) would
    otherwise look up to date to make and link stale code; the compiler cache (content-addressed)
    makes the rebuild of unchanged sources cheap."""
    os.makedirs(SRC, exist_ok=True)
    for name in os.listdir(SRC):
        if name != "build":
            p = os.path.join(SRC, name)
            shutil.rmtree(p) if os.path.isdir(p) and not os.path.islink(p) else os.remove(p)
    skip_top = lambda n: n.startswith("build") or n == ".git"
    for name in os.listdir(ROOT):
        if skip_top(name):
            continue
        p = os.path.join(ROOT, name)
        if os.path.isdir(p):
            shutil.copytree(p, os.path.join(SRC, name), symlinks=True, copy_function=shutil.copy,
                            ignore=lambda d, names: ["corpus"] if d.endswith("/fuzz") else [])
        else:
            shutil.copy(p, os.path.join(SRC, name))


def configure():
    cmd = ["cmake", "-S", SRC, "-B", BUILD, "-DCMAKE_BUILD_TYPE=Release", "-DEPUCK2_BUILD_APPS=ON",
           "-DEPUCK2_BUILD_BENCH=OFF",
           # One program per test file (the test command builds them all as one): a mutant then
           # rebuilds only the programs of the tests it runs.
           "-DEPUCK2_SPLIT_TESTS=ON"]
    if shutil.which("ccache"):
        cmd.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
    sh(cmd, check=True, stdout=subprocess.DEVNULL)


def build(targets, fast=False):
    """fast: rebuild the libraries, then only the test programs (make's TARGET/fast skips their
    dependency on the CLI, which the mutants' tests do not run, unless their group names it)."""
    if not fast:
        cmd = ["cmake", "--build", BUILD, "-j" + JOBS, "--target"] + sorted(set(targets))
        r = sh(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        return r.returncode == 0, r.stdout[-3000:]
    # Every library a test program links (TARGET/fast relinks the test against the archives as
    # they are: a mutant in lib/logs, lib/calibrate or lib/diagnose must be compiled into them first).
    # A group that names a target outside tests/ (the CLI epuck2-fit for a mutant in apps/ or a
    # test run through the binary, the ARGoS plug-in) has it rebuilt here with its dependencies;
    # the test programs are still built /fast.
    direct = [t for t in targets if not os.path.isdir(os.path.join(BUILD, "tests", "CMakeFiles", t + ".dir"))]
    targets = [t for t in targets if t not in direct]
    r = sh(["cmake", "--build", BUILD, "-j" + JOBS, "--target", "epuck2_fit", "epuck2_virtual_robot", "epuck2_logs",
            "epuck2_calibrate", "epuck2_diagnose", "epuck2_coefficients"] + direct,
           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.returncode != 0:
        return False, r.stdout[-3000:]
    # TARGET/fast skips the "depend" step that gathers the compiler's header dependencies (CMake
    # >= 3.20): run it first, or a test program that includes a mutated header is not rebuilt.
    for t in sorted(set(targets)):
        r = sh(["make", "-f", "tests/CMakeFiles/%s.dir/build.make" % t, "tests/CMakeFiles/%s.dir/depend" % t],
               cwd=BUILD, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if r.returncode != 0:
            return False, r.stdout[-3000:]
    if not targets:
        return True, ""
    # One make per program, JOBS of them at a time: the top-level Makefile is .NOTPARALLEL, so
    # `make -j2 a/fast b/fast ...` builds the programs one after another, each a single file (one
    # core idle through a header mutant's 60 programs). The /fast targets share no outputs.
    from concurrent.futures import ThreadPoolExecutor
    def one(t):
        return sh(["make", "-C", BUILD, t + "/fast"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    with ThreadPoolExecutor(max_workers=max(1, int(JOBS))) as pool:
        results = list(pool.map(one, sorted(set(targets))))
    failed = [r for r in results if r.returncode != 0]
    return not failed, (failed[0] if failed else results[-1]).stdout[-3000:]


def is_whole(pattern):
    return isinstance(pattern, tuple) and pattern[0] == "whole"


def resolve(pattern):
    """A whole group's ctest -R pattern: the name of every test its programs define (as ctest lists
    them in the configured build) and its extra tests."""
    if not is_whole(pattern):
        return pattern
    _, programs, extra = pattern
    r = sh(["ctest", "--test-dir", BUILD, "--show-only=json-v1"], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    names = []
    for t in json.loads(r.stdout).get("tests", []):
        command = t.get("command") or [""]
        if os.path.basename(command[0]) in programs:
            # By suite ("Suite.", "Prefix/Suite."): ctest's regular expressions have a size limit
            # that a list of every test name exceeds. Outside letters, digits, _ and /, a character
            # is matched as any character.
            suite = "".join(ch if ch.isalnum() or ch in "_/" else "." for ch in t["name"].split(".")[0])
            if suite + "[.]" not in names:
                names.append(suite + "[.]")
    missing = [p for p in programs if not any(
        os.path.basename((t.get("command") or [""])[0]) == p for t in json.loads(r.stdout).get("tests", []))]
    if missing:
        sys.exit("mutate: no test of %s is known to ctest in %s" % (", ".join(missing), BUILD))
    return "^(" + "|".join(names + list(extra)) + ")"


def run_tests(pattern, stop=True):
    start = time.monotonic()
    cmd = ["ctest", "--test-dir", BUILD, "-R", pattern, "--timeout", str(TIMEOUT), "-j" + TEST_JOBS]
    if stop:
        cmd.insert(5, "--stop-on-failure")
    try:
        r = sh(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=(TIMEOUT + 60) * (1 if stop else 4))
    except subprocess.TimeoutExpired:
        return False, "timeout", time.monotonic() - start, ["timeout"]
    failed = [l.strip() for l in r.stdout.splitlines() if "***Failed" in l or "***Timeout" in l or "***Exception" in l]
    names = []
    for l in failed:
        # "12/80 Test #12: Suite.Name ....***Failed  1.2 sec"
        part = l.split(":", 1)[1] if ":" in l else l
        names.append(part.split("...")[0].strip().rstrip("."))
    if "No tests were found" in r.stdout:
        return False, "no tests matched " + pattern, time.monotonic() - start, ["none matched"]
    why = "; ".join(failed[:3]) if stop else "%d failed: %s" % (len(names), ", ".join(names[:6]) + (", ..." if len(names) > 6 else ""))
    return r.returncode == 0, why, time.monotonic() - start, names


def check_list():
    """--check: every mutant's file exists and holds its original text exactly once."""
    bad = []
    for name, path, old, new, _ in MUTANTS:
        file = os.path.join(ROOT, path)
        if not os.path.isfile(file):
            bad.append("%s: %s is missing" % (name, path))
            continue
        n = open(file).read().count(old)
        if n != 1:
            bad.append("%s: its original text occurs %d times in %s (it must occur once)" % (name, n, path))
        elif old == new:
            bad.append("%s: the mutated text is the original" % name)
    names = [m[0] for m in MUTANTS]
    for n in sorted({n for n in names if names.count(n) > 1}):
        bad.append("%s: the name is used by %d mutants" % (n, names.count(n)))
    for b in bad:
        print("mutate --check: " + b)
    if bad:
        sys.exit("mutate --check: %d of %d mutants do not apply" % (len(bad), len(MUTANTS)))
    print("mutate --check: all %d mutants apply (each original text occurs once in its file)" % len(MUTANTS))


def main():
    if sys.argv[1:2] == ["--check"]:
        check_list()
        return
    words = sys.argv[1:]
    mutants = [m for m in MUTANTS if not words or any(w in m[0] for w in words)]
    copy_source()
    configure()
    groups = {}
    for m in mutants:
        groups.setdefault((tuple(m[4][0]), m[4][1]), m[4])
    # Baseline: every group's tests must pass before any mutant is judged.
    all_targets = sorted({t for g in groups.values() for t in g[0]})
    print("mutate: building %s in %s" % (" ".join(all_targets), BUILD), flush=True)
    ok, log = build(all_targets)
    if not ok:
        print(log)
        sys.exit("mutate: the unmutated copy does not build")
    patterns = {g[1]: resolve(g[1]) for g in groups.values()}
    plain = [g for g in groups.values() if not is_whole(g[1])]
    for g in plain:
        passed, why, took, _ = run_tests(patterns[g[1]])
        if not passed:
            sys.exit("mutate: the unmutated tests fail (%s): %s" % (g[1], why))
        print("mutate: baseline %s passes (%.0f s)" % (g[1], took), flush=True)
    wholes = sorted({part for g in groups.values() if is_whole(g[1]) for part in patterns[g[1]][2:-1].split("|")})
    if wholes:
        # The whole groups' tests overlap: their union runs once.
        union = "^(" + "|".join(wholes) + ")"
        passed, why, took, _ = run_tests(union, stop=False)
        if not passed:
            sys.exit("mutate: the unmutated tests of the whole groups fail: %s" % why)
        print("mutate: baseline of the whole groups passes (%.0f s)" % took, flush=True)
    results = []
    for name, path, old, new, (targets, pattern) in mutants:
        file = os.path.join(SRC, path)
        pristine = open(file).read()
        if pristine.count(old) != 1:
            results.append((name, "invalid", "the original text occurs %d times in %s" % (pristine.count(old), path), False))
            print("%-32s INVALID (%s)" % (name, results[-1][2]), flush=True)
            continue
        start = time.monotonic()
        stability_only = False
        try:
            with open(file, "w") as f:
                f.write(pristine.replace(old, new))
            # Every program whose tests run is rebuilt, not only the group's targets: a program left
            # out keeps the objects of the previous mutant's (restored) file linked in, and its tests
            # then fail for that mutant, not this one (round 10: a log reader slip "killed" the two
            # mutants after it).
            programs = list(pattern[1]) if is_whole(pattern) else []
            ok, log = build(sorted(set(targets) | set(programs)), fast=True)
            if not ok:
                # A mutant that does not compile says nothing about the tests: not counted.
                verdict, why = "invalid", "does not compile"
            else:
                passed, why, _, failed = run_tests(patterns[pattern], stop=not is_whole(pattern))
                verdict = "survived" if passed else "killed"
                if not passed and (not failed or failed == ["none matched"]):
                    # ctest failed, yet no test did (a test program missing, "Not Run"): the
                    # tests said nothing about this mutant, so it is not counted as killed.
                    verdict, why = "invalid", "ctest failed without a failing test: " + (why or "see the build")
                stability_only = not passed and is_whole(pattern) and set(failed) <= STABILITY
        finally:
            with open(file, "w") as f:
                f.write(pristine)
        results.append((name, verdict, why, stability_only))
        print("%-32s %-8s %5.0f s  %s%s" % (name, verdict.upper(), time.monotonic() - start,
                                             "(stability only) " if stability_only else "", why), flush=True)
    # Leave the build matching the source again (cheap: ccache).
    build(all_targets, fast=True)
    judged = [r for r in results if r[1] in ("killed", "survived")]
    killed = sum(1 for r in judged if r[1] == "killed")
    score = 100.0 * killed / len(judged) if judged else 0.0
    print("\nmutate: %d of %d mutants killed: score %.0f %%" % (killed, len(judged), score))
    only = [r[0] for r in judged if r[3]]
    if only:
        print("mutate: killed only by a comparison of regenerated output (%d; by correctness tests %d of %d): %s"
              % (len(only), killed - len(only), len(judged), ", ".join(only)))
    survivors = [r[0] for r in judged if r[1] == "survived"]
    if survivors:
        print("mutate: survived: " + ", ".join(survivors))
    sys.exit(0 if score >= 90.0 else 1)

main()
PY
