# The shared registered body (../shared/avatars), shirt designed on the T-pose.
REGISTER_FLAGS := --reference slim_tpose
# The shirt hugs the body: settling at the key poses with a hundredth of the
# damping lets the cloth reach its equilibrium before the rest shape grows
# after transient stretch (1,160 steps against 1,304, rest growth x1.39
# against x1.47, pattern 49 pieces against 63; see settle_damping in
# common/adapt/garment_motion.h).
SIMULATE_FLAGS := --settle-damping 0.01
