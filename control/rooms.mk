# control/rooms.mk - the rooms of control/, bottom up: a room includes and
# calls only itself and the rooms before it (control/README.md says what
# each holds). control/: the motor model, the transforms, the deadbeat,
# the blocks every method uses and the commissioning's math; control/est/:
# the proposed method's estimation, one owner (est.h); control/ctrl/: the
# controller, one ctrl_step per period. Read by the Makefile,
# firmware/f28335/target.mk and the checks (tools/check/).
CONTROL_ROOMS := control control/est control/ctrl
