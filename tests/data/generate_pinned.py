import json, numpy as np
from scalf_opt.robot import Robot
from scalf_opt.gait import GaitSpec
from scalf_opt.cycle import RobotEnergyModel
from scalf_opt.swing import make_family
out = {}
def legs_of(cycle):
    return {n: {"stance": [float(x) for x in l.stance.energy_j], "swing": [float(x) for x in l.swing.energy_j],
                "stance_heat": [float(x) for x in l.stance.heat_j], "swing_heat": [float(x) for x in l.swing.heat_j]} for n, l in cycle.legs.items()}
scalf = Robot.from_preset("scalf")
for acc in ("paper", "positive", "regenerative"):
    m = RobotEnergyModel(scalf, GaitSpec(), acc)
    out[f"scalf/reference/{acc}"] = legs_of(m.robot_cycle(make_family("reference")))
m = RobotEnergyModel(scalf, GaitSpec())
out["scalf/paper/ipopt-like"] = legs_of(m.robot_cycle(make_family("paper"), {"RF": np.array([1.889, -11.746]), "LH": np.array([1.889, 11.746])}))
rng = np.random.default_rng(7)
fam = make_family("joint-4")
th = {"RF": rng.normal(0, 0.5, fam.n_params), "LH": rng.normal(0, 0.5, fam.n_params)}
out["scalf/joint-4/random"] = {"thetas": {k: v.tolist() for k, v in th.items()}, "legs": legs_of(m.robot_cycle(fam, th))}
fam = make_family("fourier-3")
th = {"RF": np.array([0.1, 0.2, -0.1, 0.3, 0.2, -0.2, 0.1, 0.05, 0.1, -0.1])[:fam.n_params], "LH": np.zeros(fam.n_params)}
out["scalf/fourier-3/fixed"] = {"thetas": {k: v.tolist() for k, v in th.items()}, "legs": legs_of(m.robot_cycle(fam, th))}
g2 = GaitSpec(period_s=0.4, duty_cycle=0.6, step_length_m=0.3, clearance_m=0.1, stance_height_m=0.8, sample_rate_hz=300)
out["scalf/reference/gait2"] = {"gait": g2.__dict__, "legs": legs_of(RobotEnergyModel(scalf, g2).robot_cycle(make_family("reference")))}
hyq = Robot.from_preset("hyq")
out["hyq/reference"] = legs_of(RobotEnergyModel(hyq, GaitSpec().with_(stance_height_m=0.55)).robot_cycle(make_family("reference")))
# samples of RF stance + swing for reference
cyc = m.robot_cycle(make_family("reference"))
out["scalf/reference/RF_samples"] = {ph: {k: np.asarray(getattr(cyc.legs["RF"], ph).values[k]).tolist() for k in ("tau", "cyl_len", "cyl_vel", "cyl_force", "friction", "power", "q", "qd", "qdd", "foot", "grf")} for ph in ("stance", "swing")}
json.dump(out, open("tests/data/pinned_energies.json", "w"), indent=1)
print(out["scalf/reference/paper"]["RF"])
