#!/usr/bin/env bash
# Firmware rule (ARCHITECTURE.md): no dynamic memory. Fails (exit 1) when a
# firmware library of any configuration, or a linked ARM image, references
# or contains an allocator symbol; each hit is printed with its file (and
# archive member).
#
#   scripts/check-no-malloc.sh [BUILD_ROOT]      (default: build)
#
# Checked, for each configuration present under BUILD_ROOT
# (host, host-float, cortex-m4f, cortex-m7):
#   - every firmware static library <cfg>/firmware/**/libaocs_*.a
#     (libaocs_fw.a, the PIL library libaocs_pil.a and the port library):
#     undefined and defined symbols;
#   - the ARM images <cfg>/aocs_image.elf and aocs_pil.elf: every symbol the link pulled in
#     (newlib's printf, for example, would bring _malloc_r and _sbrk).
# Configurations that are not built are reported and skipped; checking
# nothing at all is an error. `make no-malloc` builds all four first.
set -euo pipefail
cd "$(dirname "$0")/.."

root=${1:-build}
configs=(host host-float cortex-m4f cortex-m7)

# Allocators of C99/POSIX and newlib's reentrant forms, and the heap growth
# call malloc brings in.
forbidden='^(malloc|free|calloc|realloc|reallocf|reallocarray|aligned_alloc|memalign|posix_memalign|valloc|pvalloc|_malloc_r|_free_r|_calloc_r|_realloc_r|_memalign_r|_malloc_usable_size_r|sbrk|_sbrk|_sbrk_r|__libc_malloc|__libc_free)$'

checked=0
failed=0

# nm_scan NM FILE: print "file[:member]: symbol (kind)" for each forbidden symbol.
nm_scan() {
  local nm=$1 file=$2
  # -A prefixes every line with the file (and archive member) name.
  "$nm" -A "$file" 2>/dev/null | awk -v re="$forbidden" '
    {
      # "lib.a:member.o:00000000 T sym", "lib.a:member.o:         U sym",
      # "image.elf:00000000 T sym": drop the address after the last colon.
      sym = $NF; kind = $(NF-1);
      if (sym ~ re) {
        where = $1; sub(/:[0-9a-fA-F]*$/, "", where);
        printf "  %s: %s (%s)\n", where, sym, (kind == "U" ? "referenced" : "defined")
      }
    }'
}

check_file() {
  local nm=$1 file=$2 hits
  if ! command -v "$nm" >/dev/null 2>&1; then
    echo "no-malloc: $nm not found (needed for $file)" >&2
    failed=1
    return
  fi
  hits=$(nm_scan "$nm" "$file")
  checked=$((checked + 1))
  if [ -n "$hits" ]; then
    echo "no-malloc: FAIL $file"
    echo "$hits"
    failed=1
  else
    echo "no-malloc: ok   $file"
  fi
}

for cfg in "${configs[@]}"; do
  dir="$root/$cfg"
  case "$cfg" in
    cortex-*) nm=arm-none-eabi-nm ;;
    *) nm=nm ;;
  esac
  if [ ! -d "$dir/firmware" ]; then
    echo "no-malloc: skip $dir (not built)"
    continue
  fi
  libs=$(find "$dir/firmware" -name 'libaocs_*.a' | sort)
  if [ -z "$libs" ]; then
    echo "no-malloc: FAIL $dir: no firmware library found"
    failed=1
  fi
  for lib in $libs; do
    check_file "$nm" "$lib"
  done
  if [ "${cfg#cortex-}" != "$cfg" ]; then
    for image in aocs_image.elf aocs_pil.elf; do
      if [ -f "$dir/$image" ]; then
        check_file "$nm" "$dir/$image"
      else
        echo "no-malloc: FAIL $dir/$image missing"
        failed=1
      fi
    done
  fi
done

if [ "$checked" -eq 0 ]; then
  echo "no-malloc: nothing checked under $root (build first: make build)" >&2
  exit 1
fi
if [ "$failed" -ne 0 ]; then
  echo "no-malloc: dynamic memory found (firmware rule: no malloc/free)" >&2
  exit 1
fi
echo "no-malloc: $checked file(s) clean"
