"""The referee ensemble's members in worker processes: the same numbers as one after another."""

import json

import numpy as np

from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.io.results import to_json
from scalf_opt.locomotion.gait import Gait
from scalf_opt.sim.ensemble import ENSEMBLE, member_processes
from scalf_opt.sim.experiment import simulation_file
from scalf_opt.sim.plan import REFERENCE_SWINGS
from scalf_opt.sim.settings import SimSettings
from scalf_opt.workers import map_in_processes


def test_the_ensemble_in_worker_processes_is_bitwise_the_serial_one(scalf):
    """Two cycles of SCalf's trot (about 3 s per ensemble): the members dealt out to this
    process and a worker, or to three processes, give the file of one process, to the last bit
    (to_json writes every float exactly), and the nominal referee's run stays in this process."""
    pipeline = EnergyPipeline(scalf, Gait())
    files, records = {}, {}
    for workers in (1, 2, 3):
        data, run = simulation_file(
            scalf, pipeline, REFERENCE_SWINGS, SimSettings(), 2, workers=workers
        )
        files[workers], records[workers] = to_json(data), run.record
    assert files[2] == files[1] and files[3] == files[1]
    for workers in (2, 3):
        for leg, tau in records[1].tau_nm.items():
            np.testing.assert_array_equal(records[workers].tau_nm[leg], tau)
    members = json.loads(files[2])["ensemble"]["members"]
    assert [m["name"] for m in members] == [p.name for p in ENSEMBLE]


def test_a_worker_process_runs_its_ensemble_itself():
    """Inside a worker the members do not start workers of their own: one process."""
    assert member_processes(4) == 4 and member_processes(0) == 1
    assert map_in_processes(member_processes, [4, None], 2) == [1, 1]
