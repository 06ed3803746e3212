# The shared registered body (../shared/avatars), jumpsuit designed on the
# T-pose (neck and cuffs pinned, open at the ankles); the shirt's seams.
REGISTER_FLAGS := --reference slim_tpose
