#!/usr/bin/env bash
# No built binary may search the working directory for libraries: every RUNPATH/RPATH entry must be
# absolute or start with $ORIGIN. An empty entry (as in "dir:" or "::") or a relative one means the
# current directory, where a planted library would run its code. Usage: check_runpath.sh FILE...
set -euo pipefail
status=0
for file in "$@"; do
  [ -f "$file" ] || { echo "$file: missing"; status=1; continue; }
  paths=$(readelf -d "$file" | sed -n 's/.*(\(RUNPATH\|RPATH\)).*\[\(.*\)\]$/\2/p')
  while IFS= read -r path; do
    [ -n "$path" ] || continue
    IFS=':' read -r -a entries <<< "$path"
    # A trailing ':' leaves no array element behind: compare the entry count with the separators.
    separators=$(tr -cd ':' <<< "$path" | wc -c)
    if [ "${#entries[@]}" -ne $((separators + 1)) ]; then
      echo "$file: runpath '$path' has an empty entry (the working directory)"; status=1
    fi
    for entry in "${entries[@]}"; do
      case "$entry" in
        /*|'$ORIGIN'|'$ORIGIN/'*) ;;
        *) echo "$file: runpath '$path' has the entry '$entry', relative to the working directory"; status=1 ;;
      esac
    done
  done <<< "$paths"
  [ $status -eq 0 ] && echo "$file: runpath ok (${paths:-none})"
done
exit $status
