"""Pastes one patch of a source mesh on top of every OBJ mesh in a folder, sized to each.

    python3 clone_onto_folder.py SOURCE X,Y,Z RADIUS FOLDER OUT
"""
import pathlib, sys
import numpy as np
import geobrush

source, point, radius = sys.argv[1], [float(c) for c in sys.argv[2].split(",")], float(sys.argv[3])
folder, out = pathlib.Path(sys.argv[4]), pathlib.Path(sys.argv[5])
out.mkdir(exist_ok=True)
evaluator = geobrush.Evaluator()  # keeps the source side's work from one target to the next
for target in sorted(folder.glob("*.obj")):
    v = geobrush.read_mesh(target).vertices
    low, high = v.min(axis=0), v.max(axis=0)
    top = v[np.argmin(np.linalg.norm(v - [(low[0] + high[0]) / 2, high[1], (low[2] + high[2]) / 2], axis=1))]
    size = np.linalg.norm(high - low) / 20  # the paste's radius: a twentieth of the target's diagonal
    try:
        result = geobrush.clone(source, point, radius, target, top, scale=size / radius, evaluator=evaluator,
                                output=out / f"{target.stem}.obj", image=out / f"{target.stem}.png")
        print(f"{target.name}: {result.mesh.face_count} faces, "
              f"{result.metrics['metrics.new_self_intersections']:.0f} new self-intersections")
    except geobrush.Error as error:
        print(f"{target.name}: {error}")
