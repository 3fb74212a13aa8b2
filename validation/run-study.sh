#!/usr/bin/env bash
# The study's drop-height, compression and tapped-density experiments at full size
# (docs/experiments.md, docs/wheat.md): test weight per bushel of two varieties' samples at
# three drop heights, confined compression to 138 kPa, loose and tapped density of the three
# fractions, each with the calibrated single-sphere and 5-sphere models; and time-step studies
# of the compression and of the single-sphere test weight on reduced samples.
#
#   validation/run-study.sh [CASE|GROUP...]   # default: every case of the groups below, in order
#   validation/run-study.sh --list            # the cases, their scenario and overrides
#   validation/run-study.sh --park            # keep the unfinished cases' checkpoints with the results
#   validation/run-study.sh --table           # only write the table and the report
#   validation/run-study.sh --validate        # check every case's scenario and overrides
#
# Groups, in the default order (single spheres first: they are cheaper):
#   tw-1s     test weight, KanMark and Garrison at h, 8h and 32h (h = 5.1 cm), single spheres
#   comp-dt   compression of a reduced sample (120 g, 30 mm high, 5 spheres) with the lid's
#             stages at 2, 5, 10 and 20 % of the critical step
#   tw-seeds  KanMark's single-sphere test weights again with another seed (a sample's chance)
#   tw-dt     test weight of a reduced Garrison sample (0.25 kg into a 250 cm3 kettle), single
#             spheres, at 20, 10 and 5 % of the Rayleigh step, three seeds each: whether the
#             single-sphere cases' step (above the critical step of the e = 0.1 pairs) matters
#   tw-pure   test weight of each pure fraction at h, single spheres: against the lab's own
#             measurements, and the mixtures' excess over them
#   tap-rate  the tapped density of a reduced sample (large, single spheres) tapped at 4.33 and
#             8.66 Hz, two seeds each: whether the rate between the taps matters; and of the
#             full-size large single spheres at 8.66 Hz, against tap-large-1s (tap-1s; hours)
#   tap-model the same reduced sample at 8.66 Hz with the 5-sphere kernels, and with single
#             spheres without rolling friction: what the taps' compaction depends on
#   comp-1s   compression at full size, large kernels, single spheres; and the same with
#             kernels ten times stiffer (how much of the compaction is overlap)
#   tap-1s    loose and tapped density, the three fractions, single spheres
#   tw-5s, comp-5s, tap-5s   the same with the 5-sphere model
#   tw-extra  test weight of KanMark at 2h, 4h and 16h, single spheres
#
# Hours to days on 2 cores. As validation/run-cup.sh: each case runs in
# runs/validation/study/CASE with a checkpoint every 5 minutes; run the script again and it
# continues unfinished cases and skips finished ones; two scripts with one thread each
# (OMP_NUM_THREADS=1) share the cases. A finished case's summary.json is kept in
# validation/results/study-runs/CASE/ (committed); --park copies the unfinished cases'
# checkpoints there, from where a checkout without the run folder continues them.
#
# One engine build per case: a checkpoint written by a build whose engine sources differ from
# this one's is not continued; the case starts again (validation/resume.sh, same_engine;
# SAME_BITS=1 continues it where bench/ab-restart showed the same bits). The build must be of
# a committed tree, so that its commit names its sources. The table
# (validation/results/study.md, validation/study_table.py) names each case's builds.
#
# Time steps: the single-sphere cases at the scenarios' 0.2 of the Rayleigh step, at which
# their per-pair parameters were calibrated and the full-size single-sphere cups ran; the
# 5-sphere cases at 0.5 of the critical step (docs/physics.md section 3), as the full-size
# 5-sphere cups. The compression's lid stages at its own press_step (0.05 Rayleigh).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bushel="${BUSHEL:-$root/build/release/bin/bushel}"
runs="$root/runs/validation/study"
kept="$root/validation/results/study-runs"
[[ "${1:-}" == --list || "${1:-}" == --validate ]] || mkdir -p "$runs" "$kept"
source "$root/validation/resume.sh"
ONE_BUILD=1
# A tapped case parked in its taps keeps its loose fill's last frame (before the stage tap) with
# its checkpoint: validation/tap_packing.py measures the loose state there, and a run continued
# from the checkpoint writes only the frames after it.
PARK_FRAME_BEFORE=tap

# The calibrated parameter sets (docs/wheat.md). Single spheres: per pair of fractions; the
# test weight's mixtures take all three pairs, a one-fraction sample the fraction's own.
declare -A one=([large]="model=1s fr_ww=0.05 fs_ww=0.172 e_ww=0.5"
  [medium]="model=1s fr_ww=0.05 fs_ww=0.486 e_ww=0.1" [small]="model=1s fr_ww=0.10 fs_ww=0.500 e_ww=0.1")
one_large=${one[large]}
one_mix="$one_large fr_wm=0.05 fs_wm=0.486 e_wm=0.1 fr_wsm=0.10 fs_wsm=0.500 e_wsm=0.1"
five="model=5s simulation.time_step=50%critical"
# The 5-sphere cases tap at twice the lab's 4.33 Hz, in half the time (55 instead of 110
# core-hours): at full size the large single spheres tapped at 8.66 Hz read 841.8 kg/m3, at 4.33 Hz
# 841.9, from one loose fill (tap-large-1s-8.66hz; validation/README.md). Each tap's fall and
# impact are the same; only the lift between them is shorter, and the grain is at rest before
# the next fall at both rates (validation/tap_series.py --phases).
five_taps="tap_frequency=8.66Hz"
kanmark="share_large=81.5% share_medium=15.5% share_small=3%"
garrison="share_large=21.8% share_medium=60.6% share_small=17.6%"
declare -A drop=([1h]=5.1cm [2h]=10.2cm [4h]=20.4cm [8h]=40.8cm [16h]=81.6cm [32h]=163.2cm)
reduced="mass=120g height=30mm fraction=large"

declare -A scenario sets
declare -A groups
add() {  # add GROUP CASE SCENARIO OVERRIDES
  groups[$1]+="${groups[$1]:+ }$2"
  scenario[$2]="$3"
  sets[$2]="$4"
}
for model in 1s 5s; do
  for sample in kanmark garrison; do
    for h in 1h 8h 32h; do
      if [ $model = 1s ]; then m=$one_mix; else m=$five; fi
      add "tw-$model" "tw-$sample-$model-$h" test-weight "$m ${!sample} drop=${drop[$h]}"
    done
  done
  if [ $model = 1s ]; then m=$one_large; else m=$five; fi
  add "comp-$model" "comp-large-$model" compression "fraction=large $m"
  add "comp-$model" "comp-large-$model-stiff" compression "fraction=large $m materials.wheat.shear_modulus=224MPa"
  for fraction in large medium small; do
    if [ $model = 1s ]; then m=${one[$fraction]}; else m="$five $five_taps"; fi
    add "tap-$model" "tap-$fraction-$model" tapped-density "fraction=$fraction $m"
  done
done
for percent in 20 10 5 2; do  # (the cheapest first)
  add comp-dt "comp-dt-$percent" compression "$reduced $five press_step=$percent%critical"
done
for h in 1h 8h 32h; do  # (the same runs with another seed: how far a difference is the sample's chance)
  add tw-seeds "tw-kanmark-1s-$h-seed2" test-weight "$one_mix $kanmark drop=${drop[$h]} seed=2"
done
declare -A pure=([large]="share_large=100% share_medium=0% share_small=0%"
  [medium]="share_large=0% share_medium=100% share_small=0%" [small]="share_large=0% share_medium=0% share_small=100%")
for fraction in large medium small; do  # (its pairs take the fraction's own set, as in one_mix)
  add tw-pure "tw-$fraction-1s-1h" test-weight "$one_mix ${pure[$fraction]} drop=${drop[1h]}"
done
for h in 2h 4h 16h; do
  add tw-extra "tw-kanmark-1s-$h" test-weight "$one_mix $kanmark drop=${drop[$h]}"
done
# The single-sphere test weight's time step, on a reduced sample: 0.2 of the Rayleigh step, at
# which the single-sphere parameters were calibrated, is 1.19 times the critical step of the
# pairs with restitution 0.1 (their tangential mode, docs/physics.md section 3); 10 and 5 % are
# 0.59 and 0.30 of it, inside the range the dt-independence study found sound. Garrison, whose
# medium and small kernels make most of its pairs such pairs; a quarter of the mass into a
# kettle of 250 cm3 and 60 mm (about the full kettle's shape), three seeds at each step.
reduced_tw="$one_mix $garrison drop=${drop[1h]} mass=0.25kg kettle_volume=250cm3 kettle_diameter=60mm"
for percent in 20 10 5; do  # (the cheapest first)
  for seed in 1 2 3; do
    add tw-dt "tw-dt-$percent-seed$seed" test-weight \
      "$reduced_tw simulation.time_step=$percent%rayleigh seed=$seed"
  done
done
# The tapping rate, on a reduced sample: the same 500 taps of 3 mm at the lab's 4.33 Hz and at
# twice that, two seeds each. The impact of a tap (a 3 mm free fall) is the same at both; only
# the slow lift between taps is shorter. The faster rate's struck density is 0.66 % higher, 4.5
# standard deviations, but its grain before the strike is not shown to be denser
# (validation/README.md). And the full-size large single spheres at 8.66 Hz, from the same loose
# fill as tap-large-1s: the rate does not move the full-size result (-0.1 kg/m3 struck).
reduced_cylinder="height=30mm mass=110g top_up=40g extension_height=30mm"
reduced_tap="fraction=large $one_large $reduced_cylinder"
for hz in 4.33 8.66; do
  for seed in 1 2; do
    add tap-rate "tap-rate-${hz}hz-seed$seed" tapped-density "$reduced_tap tap_frequency=${hz}Hz seed=$seed"
  done
done
add tap-rate tap-large-1s-8.66hz tapped-density "fraction=large $one_large tap_frequency=8.66Hz"
# What the taps' compaction depends on, on the same reduced sample at 8.66 Hz (seed 1): the full-size
# large single spheres' compressibility is 0.0325 where the lab's kernels' is 0.051
# (validation/README.md). The kernels' shape: the 5-sphere set; the single spheres' stand-in for
# it, their rolling friction: none between kernels. Each against tap-rate-8.66hz-seed1 and -seed2,
# which compact more than the full-size cylinder: these show what the taps depend on, not
# whether the full-size gap closes.
model_tap="fraction=large $reduced_cylinder tap_frequency=8.66Hz seed=1"
no_rolling="${one_large/fr_ww=0.05/fr_ww=0}"
[ "$no_rolling" != "$one_large" ] || { echo "run-study.sh: no fr_ww=0.05 in the large set to turn off" >&2; exit 2; }
add tap-model tap-model-5s-seed1 tapped-density "$model_tap $five"
add tap-model tap-model-no-rolling-seed1 tapped-density "$model_tap $no_rolling"
order=(tw-1s comp-dt tw-seeds tw-dt tw-pure comp-1s tap-rate tap-model tap-1s tw-5s comp-5s tap-5s tw-extra)
all=()
for g in "${order[@]}"; do read -r -a members <<< "${groups[$g]}"; all+=("${members[@]}"); done

finished() { run_finished "$kept/$1"; }

park() { park_unfinished "$runs" "$kept" "${all[@]}"; }

# The finished tapped cases' density tap by tap and kinetic energy through a tap's period
# (validation/tap_series.py, into validation/results/tap-series.csv and tap-phases.csv), and the
# full-size ones' solid fraction in the cylinder's core and across it (validation/tap_packing.py,
# into tap-packing.csv), from the run folders this checkout has, one case at a time (one that
# fails leaves the others); the rows of cases whose folders are gone stay.
tap_series() {
  local c results="$root/validation/results"
  for c in "${all[@]}"; do
    if [[ "$c" == tap-* ]] && run_finished "$runs/$c" && [ -f "$runs/$c/timeseries.csv" ]; then
      /usr/bin/python3 "$root/validation/tap_series.py" --update --csv "$results/tap-series.csv" \
        --phases "$results/tap-phases.csv" "$runs/$c" > /dev/null ||
        echo "run-study.sh: validation/tap_series.py failed on $c (above); the table goes on without it" >&2
      if [[ "$c" =~ ^tap-(large|medium|small)-[0-9]+s(-[0-9.]+hz)?$ ]]; then
        /usr/bin/python3 "$root/validation/tap_packing.py" --update --csv "$results/tap-packing.csv" "$runs/$c" \
          > /dev/null || echo "run-study.sh: validation/tap_packing.py failed on $c (above); the table goes on" >&2
      fi
    fi
  done
}

# The tables of every case so far (validation/study_table.py), and the report of the finished
# ones beside the lab values.
table() {  # (through a file of its own: two scripts may write it at once)
  local tmp
  tap_series
  tmp=$(mktemp "$root/validation/results/study.md.XXXXXX")
  /usr/bin/python3 "$root/validation/study_table.py" "$runs" "$kept" "$root/data/reference_values.csv" \
    "${all[@]}" > "$tmp"
  mv "$tmp" "$root/validation/results/study.md"
}
# The lab's values: the study's (built in), and the test weights its data expect of the samples
# (study_table.py --expected). The reduced samples' studies are drawn without them: their
# small vessels read apart from the lab by their walls, and compare only with each other.
expected="$root/validation/results/study-expected.csv"
report() {  # report OUT TITLE full|reduced CASE...: `bushel report` of those cases that have finished
  local out="$1" title="$2" size="$3" c dirs=() refs=(--reference none)
  shift 3
  for c in "$@"; do
    if finished "$c"; then dirs+=("validation/results/study-runs/$c"); fi
  done
  [ ${#dirs[@]} -gt 0 ] || return 0
  if [ "$size" = full ]; then
    local tmp
    tmp=$(mktemp "$expected.XXXXXX")
    /usr/bin/python3 "$root/validation/study_table.py" --expected "$root/data/reference_values.csv" > "$tmp"
    mv "$tmp" "$expected"
    refs=(--reference study --reference "$expected")
  fi
  (cd "$root" && "$bushel" report "${dirs[@]}" --out "validation/results/$out" --title "$title" "${refs[@]}")
}
reports() {  # the full-size cases, and apart from them each study on a reduced sample
  local c full=() dt=() twdt=() rate=() model=()
  for c in "${all[@]}"; do
    case "$c" in
      comp-dt-*) dt+=("$c") ;;
      tw-dt-*) twdt+=("$c") ;;
      tap-rate-*) rate+=("$c") ;;
      tap-model-*) if finished "$c"; then model+=("$c"); fi ;;  # (drawn beside the twins they are set against)
      tap-*hz) rate+=("${c%-*}" "$c") ;;  # (another rate, without the lab's values: beside its twin)
      *) full+=("$c") ;;
    esac
  done
  report study "The study's experiments at full size" full "${full[@]}"
  report study-time-step "Compression: the lid's time step (reduced sample)" reduced "${dt[@]}"
  report study-tw-time-step "Test weight: the time step of single spheres (reduced sample)" reduced "${twdt[@]}"
  report study-tap-rate "Tapped density: the tapping rate (reduced sample; full-size twins)" reduced "${rate[@]}"
  [ ${#model[@]} -eq 0 ] || report study-tap-model "Tapped density: other kernels (reduced sample, 8.66 Hz)" \
    reduced tap-rate-8.66hz-seed1 tap-rate-8.66hz-seed2 "${model[@]}"
}

case_args() {  # case_args CASE: the case's overrides as bushel's options, in args
  args=(--set parameters.frame_interval=1s)
  # shellcheck disable=SC2086  # (the overrides split into words on purpose)
  set_args ${sets[$1]}
}
validate() {  # `bushel validate` of every case's scenario with its overrides (seconds, not hours)
  local c
  for c in "${all[@]}"; do
    case_args "$c"
    "$bushel" validate "$root/scenarios/${scenario[$c]}.yaml" "${args[@]}" > /dev/null ||
      { echo "run-study.sh: case $c does not validate" >&2; return 1; }
  done
  echo "all ${#all[@]} cases validate"
}

case "${1:-}" in
  --list)
    for c in "${all[@]}"; do printf '%-27s %-15s %s\n' "$c" "${scenario[$c]}" "${sets[$c]}"; done
    exit 0 ;;
  --validate) validate; exit ;;
  --park) park; table; exit 0 ;;
  --table) table; reports; exit 0 ;;
esac
if [[ "$(this_build)" == *uncommitted* ]]; then
  echo "run-study.sh: $bushel was built with uncommitted changes; build it from a committed tree," \
    "so that its commit names the engine that ran each case" >&2
  exit 2
fi
cases=()
for a in "${@:-${order[@]}}"; do
  if [ -n "${groups[$a]:-}" ]; then read -r -a members <<< "${groups[$a]}"; cases+=("${members[@]}")
  elif [ -n "${scenario[$a]:-}" ]; then cases+=("$a")
  else echo "unknown case or group '$a' (run-study.sh --list; groups: ${order[*]})" >&2; exit 2
  fi
done

for c in "${cases[@]}"; do
  if finished "$c"; then echo "$c: finished before, kept ($kept/$c)" >&2; continue; fi
  if run_failed "$kept/$c"; then
    echo "$c: failed before ($kept/$c/summary.json); remove it to run it again" >&2
    continue
  fi
  case_args "$c"
  rc=0
  run_case "$c" "$runs/$c" "$kept/$c" "$root/scenarios/${scenario[$c]}.yaml" "${args[@]}" || rc=$?
  if [ "$rc" -eq "$run_busy" ]; then continue; fi  # (another script runs it: the next case)
  table
  if [ "$rc" -ne 0 ] && ! run_failed "$runs/$c"; then  # (a failed case: the next one)
    echo "$c: stopped (exit $rc); run the script again to continue" >&2
    exit "$rc"
  fi
done
table
cat "$root/validation/results/study.md"
reports
