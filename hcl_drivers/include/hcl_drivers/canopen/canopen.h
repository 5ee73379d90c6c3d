// Our small CANopen master layer (CiA 301 subset): one protocol piece per header.
#pragma once

#include "hcl_drivers/canopen/cob_id.h"
#include "hcl_drivers/canopen/nmt.h"
#include "hcl_drivers/canopen/pdo.h"
#include "hcl_drivers/canopen/remote_node.h"
#include "hcl_drivers/canopen/sdo.h"
