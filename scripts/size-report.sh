#!/usr/bin/env bash
# Memory report of the flight code on both ARM targets (builds nothing:
# `make size-report` builds build/cortex-m4f and build/cortex-m7 first).
#
#   scripts/size-report.sh [BUILD_ROOT]     (default: build)
#
# 1. Per module (each firmware .c object: math/*, control/<law>, executive/*,
#    the PIL library pil/* and the Cortex-M port), text/data/bss from arm-none-eabi-size, side by
#    side for cortex-m4f (float) and cortex-m7 (double). Object sizes count
#    every function of the module; the image keeps only what is called
#    (--gc-sections), so the image total is the figure that flies.
# 2. Image totals (aocs_image.elf: flight code + port + in-image test loop).
# 3. Worst-case stack per law step (scripts/stack-report.py, from the
#    -fstack-usage / -fcallgraph-info files written next to the objects).
set -euo pipefail
cd "$(dirname "$0")/.."

root=${1:-build}
targets=(cortex-m4f cortex-m7)
size=arm-none-eabi-size
command -v "$size" >/dev/null || { echo "size-report: $size not installed (scripts/setup.sh)" >&2; exit 1; }

for t in "${targets[@]}"; do
  if [ ! -f "$root/$t/aocs_image.elf" ]; then
    echo "size-report: $root/$t/aocs_image.elf missing (run: make build-$t)" >&2
    exit 1
  fi
done

# module name of an object: path below src/ (or port/) without .c.obj
module_of() {
  local obj=$1
  case "$obj" in
    */aocs_fw.dir/src/*) obj=${obj#*/aocs_fw.dir/src/} ;;
    */aocs_fw.dir/gains/*) obj=gains/${obj#*/aocs_fw.dir/gains/} ;;
    */aocs_pil.dir/src/*) obj=pil/${obj#*/aocs_pil.dir/src/} ;;
    */aocs_port_cm.dir/*) obj=port/${obj#*/aocs_port_cm.dir/} ;;
  esac
  obj=${obj%.obj}
  echo "${obj%.c}"
}

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

for t in "${targets[@]}"; do
  find "$root/$t/firmware" \( -path '*/aocs_fw.dir/*' -o -path '*/aocs_pil.dir/*' -o -path '*/aocs_port_cm.dir/*' \) \
       -name '*.obj' | sort > "$tmp/$t.objs"
  : > "$tmp/$t.sizes"
  while IFS= read -r obj; do
    # Berkeley format: text data bss dec hex filename
    read -r text data bss _ < <("$size" -B "$obj" | tail -n 1)
    printf '%s %s %s %s\n' "$(module_of "$obj")" "$text" "$data" "$bss" >> "$tmp/$t.sizes"
  done < "$tmp/$t.objs"
done

echo "Firmware modules, bytes (arm-none-eabi-size of each object, before --gc-sections)"
cat "$tmp/cortex-m4f.sizes" "$tmp/cortex-m7.sizes" | cut -d' ' -f1 | sort -u > "$tmp/modules"
# POSIX awk (Debian ships mawk): file 1 = sorted module names, files 2-3 = sizes
awk '
  FNR == 1 { f++ }
  f == 1 { names[++n] = $1; next }
  { key = $1; t[f - 1, key] = $2; d[f - 1, key] = $3; b[f - 1, key] = $4 }
  END {
    printf "%-26s | %28s | %28s\n", "module", "cortex-m4f (float)", "cortex-m7 (double)"
    printf "%-26s | %8s %8s %8s  | %8s %8s %8s\n", "", "text", "data", "bss", "text", "data", "bss"
    printf "%s\n", "---------------------------+------------------------------+------------------------------"
    for (i = 1; i <= n; i++) {
      k = names[i]; row = sprintf("%-26s |", k)
      for (j = 1; j <= 2; j++) {
        if ((j, k) in t) { row = row sprintf(" %8d %8d %8d  |", t[j, k], d[j, k], b[j, k]); T[j] += t[j, k]; D[j] += d[j, k]; B[j] += b[j, k] }
        else { row = row sprintf(" %8s %8s %8s  |", "-", "-", "-") }
      }
      print substr(row, 1, length(row) - 1)
    }
    printf "%s\n", "---------------------------+------------------------------+------------------------------"
    printf "%-26s | %8d %8d %8d  | %8d %8d %8d\n", "sum of objects", T[1], D[1], B[1], T[2], D[2], B[2]
  }' "$tmp/modules" "$tmp/cortex-m4f.sizes" "$tmp/cortex-m7.sizes"

echo
echo "Images (linked with --gc-sections; bss includes the 16 KiB main stack region)"
printf '%-12s %8s %8s %8s   %s\n' target text data bss file
for t in "${targets[@]}"; do
  read -r text data bss _ < <("$size" -B "$root/$t/aocs_image.elf" | tail -n 1)
  printf '%-12s %8d %8d %8d   %s\n' "$t" "$text" "$data" "$bss" "$root/$t/aocs_image.elf"
done

echo
python3 scripts/stack-report.py --paths \
  "cortex-m4f=$root/cortex-m4f" "cortex-m7=$root/cortex-m7"
