#!/usr/bin/env bash
# Gives `geobrush` every file of at most 1 MB under the folders named (meshes to
# `geobrush render`, anything else to `geobrush run` as a graph) and checks that each run ends
# with exit status 0, 1 or 2 within 5 s and 1 GB, with no file left behind by a failed run.
# A mesh is a file named .obj, .ply, .off or .stl, or any file in a folder whose name ends in
# mesh_obj, mesh_ply, mesh_off or mesh_stl (the fuzz corpora, whose files have no extension).
#   tests/fuzz/any_file.sh BUILD_DIR FOLDER...
# Prints the slowest run and the largest peak memory; needs GNU time (/usr/bin/time).
set -euo pipefail
geobrush=$(cd "$1" && pwd)/bin/geobrush
shift
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
status=0 files=0 slowest=0 slowestFile="" largest=0 largestFile=""
while IFS= read -r -d '' file; do
  files=$((files + 1))
  out="$work/out"
  rm -rf "$out" && mkdir -p "$out"
  mesh=$file
  if [[ ! ${file,,} =~ \.(obj|ply|off|stl)$ && $(dirname "$file") =~ mesh_(obj|ply|off|stl)$ ]]; then
    mesh="$work/mesh.${BASH_REMATCH[1]}"
    cp "$file" "$mesh"
  fi
  case "${mesh,,}" in
    *.obj | *.ply | *.off | *.stl)
      command=("$geobrush" render "$mesh" --backend cpu --width 64 --height 48 -o "$out/x.png") ;;
    *) command=("$geobrush" run "$file" --out "$out" --quiet) ;;
  esac
  set +e
  /usr/bin/time -o "$work/usage" -f "%e %M" timeout 5 "${command[@]}" >/dev/null 2>"$work/err"
  code=$?
  set -e
  read -r seconds kilobytes < <(tail -n 1 "$work/usage")
  if ((code > 2)); then
    status=1
    echo "FAILED (exit $code): ${command[*]}"
    head -c 2000 "$work/err"
  elif ((code != 0)) && [[ -n $(ls -A "$out") ]]; then
    status=1
    echo "FAILED (exit $code left files behind: $(ls -A "$out")): ${command[*]}"
  fi
  if ((kilobytes > 1048576)); then
    status=1
    echo "FAILED (peak memory $((kilobytes / 1024)) MB): ${command[*]}"
  fi
  if awk "BEGIN { exit !($seconds > $slowest) }"; then slowest=$seconds slowestFile=$file; fi
  if ((kilobytes > largest)); then largest=$kilobytes largestFile=$file; fi
done < <(find "$@" -type f -size -1025k -print0 | sort -z)
echo "$files files: slowest run ${slowest} s ($slowestFile), largest peak memory $((largest / 1024)) MB ($largestFile)"
exit $status
