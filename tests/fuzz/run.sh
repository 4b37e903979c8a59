#!/usr/bin/env bash
# Runs every fuzz target of a build made with -DGEOBRUSH_FUZZ=ON on its seed corpus.
#   tests/fuzz/run.sh BUILD_DIR [SECONDS_EACH | -runs=N]
# Fails on any crash, sanitizer report, leak, input slower than 1 s or use of more than 2 GB.
# New inputs go to a temporary folder, or to $FUZZ_WORK (kept) when it is set; the seed corpora
# stay as they are.
set -euo pipefail
build=$(cd "$1" && pwd)
limit=${2:-30}
here=$(cd "$(dirname "$0")" && pwd)
if [[ $limit == -runs=* ]]; then budget=$limit; else budget=-max_total_time=$limit; fi

corpus_of() {
  case $1 in
    fuzz_mesh_*) echo "$here/corpus/${1#fuzz_}" ;;
    fuzz_graph) echo "$here/corpus/graph $here/../../graphs" ;;
    fuzz_set) echo "$here/corpus/set" ;;
  esac
}

if [[ -n ${FUZZ_WORK:-} ]]; then
  work=$FUZZ_WORK
  mkdir -p "$work"
else
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
# One target: its summary line, or its failure with the log's tail and the inputs that failed
# (copied next to the target), into $work/$name.result.
fuzz_one() {
  local target=$1 name
  name=$(basename "$target")
  mkdir -p "$work/$name"
  local dict="$here/$name.dict"
  local options=(-timeout=1 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1
                 -artifact_prefix="$work/$name-" "$budget")
  [[ -f $dict ]] && options+=(-dict="$dict")
  # shellcheck disable=SC2046
  if "$target" "${options[@]}" "$work/$name" $(corpus_of "$name") >"$work/$name.log" 2>&1; then
    local runs rss
    runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$work/$name.log" | grep -o '[0-9]*$')
    rss=$(grep -o 'stat::peak_rss_mb: *[0-9]*' "$work/$name.log" | grep -o '[0-9]*$')
    echo "$name: ok, $runs runs, peak RSS $rss MB" >"$work/$name.result"
  else
    {
      echo "$name: FAILED"
      tail -n 60 "$work/$name.log"
      for artifact in "$work/$name"-*; do
        [[ -e $artifact ]] && echo "input: $artifact ($(wc -c <"$artifact") bytes)" &&
          cp "$artifact" "$build/fuzz/"
      done
    } >"$work/$name.result"
  fi
}

# The targets run side by side, one per processor; each is single-threaded.
slots=$(nproc)
targets=("$build"/fuzz/fuzz_*)
for target in "${targets[@]}"; do
  while (($(jobs -rp | wc -l) >= slots)); do wait -n || true; done
  fuzz_one "$target" &
done
wait
status=0
for target in "${targets[@]}"; do
  result="$work/$(basename "$target").result"
  if [[ -f $result ]]; then cat "$result"; else echo "$(basename "$target"): FAILED, no result"; status=1; fi
  grep -q ': FAILED' "$result" 2>/dev/null && status=1
done
exit $status
