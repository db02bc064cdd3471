#!/usr/bin/env bash
# Static analysis gate of the firmware: cppcheck 2.10 with the MISRA C:2012
# addon plus cppcheck's own warning/style/performance/portability checks.
# Zero findings or exit 1.
#
#   scripts/static-analysis.sh            (make static-analysis)
#
# Suppressions come only from firmware/MISRA-DEVIATIONS.md (table rows
# "| <rule> | `<glob>`, ... | <reason> |"); no inline suppressions. The one
# filter applied afterwards (cppcheck 2.10's 9.3 false positive on struct
# objects initialised from an expression) is described in that file too.
#
# Two passes, because exactly one HAL port is linked into any program and
# both define the hal.h functions (MISRA 8.6 across ports otherwise):
#   host    firmware/src + gains + pil + port/posix      --platform=unix64
#   target  firmware/src + gains + pil + port/cortex-m   --platform=unix32 (ILP32, as ARM)
# firmware/pil is the PIL library (frame codec, budgets): not flight code,
# but it runs on the target and keeps every firmware rule, so it is analysed
# with the flight library.
# cppcheck checks each preprocessor configuration it finds, so both the
# double and the float (AOCS_REAL_IS_FLOAT) builds are analysed.
set -euo pipefail
cd "$(dirname "$0")/.."

deviations=firmware/MISRA-DEVIATIONS.md
work=${AOCS_SA_DIR:-build/static-analysis}
jobs=${JOBS:-2}
mkdir -p "$work"

command -v cppcheck >/dev/null || { echo "static-analysis: cppcheck not installed (scripts/setup.sh)" >&2; exit 1; }

# ---- suppressions from the deviations table ----
supp="$work/suppressions.txt"
: > "$supp"
# Only the first table ("## Deviations") is turned into suppressions.
awk '
  /^## / { in_dev = ($0 == "## Deviations") }
  in_dev && /^\|/ {
    n = split($0, cell, "|")
    rule = cell[2]; scope = cell[3]
    gsub(/^[ \t]+|[ \t]+$/, "", rule)
    if (rule !~ /^[0-9]+\.[0-9]+$/) next           # header, separator
    m = split(scope, globs, ",")
    for (i = 1; i <= m; i++) {
      g = globs[i]; gsub(/[` \t]/, "", g)
      if (g == "") continue
      printf "misra-c2012-%s:%s\n", rule, g
    }
  }' "$deviations" > "$supp"
if [ ! -s "$supp" ]; then
  echo "static-analysis: no deviations parsed from $deviations (format changed?)" >&2
  exit 1
fi
echo "static-analysis: $(wc -l < "$supp") suppression(s) from $deviations"

template='{file}:{line}: {severity}: {id}: {message}'
common=(--addon=misra --std=c99 --language=c
        --enable=warning,style,performance,portability
        --suppress=missingIncludeSystem
        --suppressions-list="$supp"
        --error-exitcode=1 -q -j "$jobs"
        "--template=$template"
        -I firmware/include -I firmware -I firmware/pil/include)

raw="$work/findings-raw.txt"
: > "$raw"
sources=(firmware/src)
[ -d firmware/gains ] && sources+=(firmware/gains)
[ -d firmware/pil/src ] && sources+=(firmware/pil/src)

run_pass() {
  local name=$1; shift
  mkdir -p "$work/$name"
  echo "static-analysis: pass '$name': $*"
  # exit status judged below, after the documented 9.3 filter
  cppcheck "${common[@]}" --cppcheck-build-dir="$work/$name" "$@" 2>> "$raw" || true
}

host_src=("${sources[@]}")
[ -d firmware/port/posix ] && host_src+=(firmware/port/posix)
run_pass host --platform=unix64 "${host_src[@]}"

target_src=("${sources[@]}")
if [ -d firmware/port/cortex-m ]; then
  target_src+=(firmware/port/cortex-m)
fi
run_pass target --platform=unix32 -I firmware/port/cortex-m "${target_src[@]}"

# ---- filter (MISRA-DEVIATIONS.md, "Tool false positives") and verdict ----
findings="$work/findings.txt"
filtered=0
: > "$findings"
while IFS= read -r line; do
  case "$line" in
    *": misra-c2012-9.3:"*)
      file=${line%%:*}; rest=${line#*:}; lno=${rest%%:*}
      if [ -f "$file" ] && ! sed -n "${lno}p" "$file" | grep -q '{'; then
        filtered=$((filtered + 1))
        continue
      fi ;;
  esac
  printf '%s\n' "$line" >> "$findings"
done < <(grep -E '^[^ ]+:[0-9]+: ' "$raw" | sort -u)

# cppcheck also prints tool errors without file:line (addon crash, bad option)
if grep -vE '^[^ ]+:[0-9]+: |^$|^nofile:0:' "$raw" | grep -q .; then
  echo "static-analysis: cppcheck reported errors:" >&2
  grep -vE '^[^ ]+:[0-9]+: |^$' "$raw" >&2
  exit 1
fi

count=$(wc -l < "$findings")
echo "static-analysis: $filtered cppcheck 9.3 false positive(s) filtered (see $deviations)"
if [ "$count" -ne 0 ]; then
  cat "$findings"
  echo "static-analysis: by check:"
  awk -F': ' '{print $3}' "$findings" | sort | uniq -c | sort -rn
  echo "static-analysis: FAIL, $count finding(s) (fix, or add a deviation with a reason to $deviations)" >&2
  exit 1
fi
echo "static-analysis: PASS (0 findings)"
