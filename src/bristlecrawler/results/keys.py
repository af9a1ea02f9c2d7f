"""The JSON keys of every result the package writes, spelled once (units in the names).

A run's ``summary.json``, a design study's outputs, a drag test's ``summary.json``, the
reduced job's and the prediction's results all name their numbers with these; readers
(the report, the figures, the cache) read them with the same names.
"""

from __future__ import annotations

# The motion of a run and its cost (any model).
NET_ADVANCE_MM = "net_advance_mm"
ADVANCE_PER_CYCLE_MM = "advance_per_cycle_mm"
WORK_MJ = "work_mJ"
WORK_PER_CYCLE_MJ = "work_per_cycle_mJ"
LAST_CYCLE_ADVANCE_MM = "last_cycle_advance_mm"
COST_OF_TRANSPORT = "cost_of_transport_mJ_per_mm"
MEAN_ABS_CONNECTOR_FORCE_N = "mean_abs_connector_force_N"
MAX_ABS_CONNECTOR_FORCE_N = "max_abs_connector_force_N"
ENERGY_BALANCE_REL_ERROR = "energy_balance_rel_error"

# The solve and its cost.
STEPS = "steps"
NEWTON_ITERATIONS = "newton_iterations"
WALL_TIME_S = "wall_time_s"

# The end of the gravity step.
SETTLE_SPEED_MM_S = "settle_speed_mm_s"
SETTLE_CREEP_MM = "settle_creep_mm"

# The three parameters of the paper's reduced model, as a drag test gives them.
K_N_PER_MM = "k_N_per_mm"
FP_N = "fp_N"
FN_N = "fn_N"
