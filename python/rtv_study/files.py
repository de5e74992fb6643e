"""A run's files travel with its task (vehicle, tire and road files as bytes), never through a shared disk: the
worker writes them into a folder of its own for the run, which the model reads as an FMU reads its resources,
and removes it after."""
import os
import tempfile


def with_files(task, call):
    """`call(request)` with the task's files written to a fresh folder named in the request."""
    with tempfile.TemporaryDirectory(prefix="rtv-run-") as folder:
        for name, data in task["files"].items():
            # Names are made by the study reader (vehicle.json, vehicle_tire.tir, a road's base name): plain
            # names, never paths.
            if os.path.basename(name) != name or name in ("", ".", ".."):
                raise ValueError(f"a task file name must be a plain name: {name!r}")
            with open(os.path.join(folder, name), "wb") as f:
                f.write(data)
        return call(dict(task["request"], files_dir=folder))
