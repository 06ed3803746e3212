# The shared registered body (../shared/avatars), shirt designed on the T-pose.
REGISTER_FLAGS := --reference slim_tpose
