"""The paper application, apart from the library: reproduces the paper's three experiments
(section "Simulation results") on the iCub, in the paper's setting, and explains every outcome
with the closed loop's linearisation. Run it with ``python -m sea_momentum reproduce``.

Every experiment is also run with the controller sampled at 1 kHz with zero-order hold (one 1 ms
plant step per tick, the setting of the earlier results), and the stability map covers the
sampled-data loop from 100 Hz to 10 kHz. Modules, by concern:

- :mod:`~sea_momentum.paper.setting`: the paper's settings and reported outcomes;
- :mod:`~sea_momentum.paper.session`: where the scenarios are and the outputs go, the runs;
- :mod:`~sea_momentum.paper.experiments`: the experiments' runs and the saturation's numbers;
- :mod:`~sea_momentum.paper.evidence`: linearisations, stability margins, growth-rate curve;
- :mod:`~sea_momentum.paper.stability_map`: sweeps over damping scale and control rate;
- :mod:`~sea_momentum.paper.figures`: the figures and the pictures of the robot;
- :mod:`~sea_momentum.paper.outcomes`: the table, the evidence text, outcomes.md, summary.json;
- :mod:`~sea_momentum.paper.pipeline`: :func:`reproduce`, all of it in order.

Writes to ``out``:

- ``figure1_tracking_damping.png``: lateral CoM error for controller damping estimates x1.0,
  x1.45, x1.6, x0.4 (continuous);
- ``figure2_rigid_vs_sea.png``: joint error norm after the 1 degree upper-body step, rigid and
  SEA controllers (continuous);
- ``figure3_saturation.png``: stance ankle roll motor velocity with the springs at rest at the
  start, with and without the 0.34 Nm limit (continuous);
- ``stability_map.png``: damping estimate scale against control rate (and continuous): stable
  or not and the CoM error from a sweep, with the eigenvalue boundary drawn over it;
- ``growth_rate_damping.png``: growth rate of the least stable mode against the damping
  estimate scale (continuous, and 1 kHz for contrast), the paper's x0.4, x1.45, x1.6 marked;
- ``{tracking,step_sea,step_rigid,saturation}_strip.png`` and ``.gif``: the robot during each
  experiment;
- one MCAP log per paper scenario, ``summary.json`` and ``outcomes.md`` (each experiment: the
  paper's outcome, ours in the paper's setting and at 1 kHz, and the evidence for every
  disagreement, all computed by this run).
"""

from .pipeline import reproduce

__all__ = ["reproduce"]
