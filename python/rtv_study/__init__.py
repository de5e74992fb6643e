"""Parameter studies of rt-vehicle on Dask distributed (docs/studies.md).

    import rtv_study
    study = rtv_study.load("examples/studies/dlc_speed_damper.toml")   # checked: StudyError with its line
    table = rtv_study.run(study, workers=2)                              # pyarrow Table, also DIR/results.parquet
    df = table.to_pandas()                                               # if pandas is installed
"""
from .native import NativeError, describe
from .runner import run, schema
from .study import Study, StudyError, load

__all__ = ["load", "run", "schema", "describe", "Study", "StudyError", "NativeError"]
