// Everything of the localization filter in one include.
#pragma once
#include "hal_nodes/mcl/checks/beacon_belts.h"
#include "hal_nodes/mcl/checks/bumpers.h"
#include "hal_nodes/mcl/checks/compass.h"
#include "hal_nodes/mcl/checks/rangers.h"
#include "hal_nodes/mcl/checks/table_model.h"
#include "hal_nodes/mcl/filter.h"
#include "hal_nodes/mcl/motion/odometry_input.h"
