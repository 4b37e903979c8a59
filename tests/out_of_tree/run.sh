#!/usr/bin/env bash
# Installs this build, builds tests/out_of_tree/plugin against the installed package
# (CMake config), and runs a graph that uses the out-of-tree node.
set -euo pipefail
build=$1
source=$2
work=$build/out_of_tree
rm -rf "$work"
cmake --install "$build" --prefix "$work/prefix" > /dev/null
cmake -S "$source/tests/out_of_tree/plugin" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build "$work/build" > /dev/null
export GEOBRUSH_PLUGIN_PATH=$work/build/plugins
nodes=$("$work/prefix/bin/geobrush" nodes --json)
grep -q '"id": "example.centre"' <<< "$nodes"
cat > "$work/graph.json" <<'JSON'
{"format": "geobrush-graph", "formatVersion": 1,
 "nodes": {"shape": {"type": "geobrush.primitive", "typeVersion": 1,
                     "params": {"shape": "torus", "resolution": 16}},
           "move": {"type": "geobrush.transform", "typeVersion": 1,
                    "params": {"translate": [3.0, -2.0, 5.0]}},
           "centre": {"type": "example.centre", "typeVersion": 1},
           "save": {"type": "geobrush.save_mesh", "typeVersion": 1, "params": {"path": "centred.obj"}}},
 "connections": [{"from": "shape.mesh", "to": "move.mesh"}, {"from": "move.mesh", "to": "centre.mesh"},
                 {"from": "centre.mesh", "to": "save.mesh"}]}
JSON
"$work/prefix/bin/geobrush" run "$work/graph.json" --quiet
# The torus is symmetric about the origin: every coordinate's mean is ~0 again.
awk '$1 == "v" { x += $2; y += $3; z += $4; n++ }
     END { if (n == 0 || (x/n)^2 + (y/n)^2 + (z/n)^2 > 1e-12) { print "not centred"; exit 1 } }' \
  "$work/centred.obj"
echo "out-of-tree plugin: ok"
