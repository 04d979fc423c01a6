/* igea.h - umbrella header: every public igea header. */
#ifndef IGEA_H
#define IGEA_H
#include "igea/common.h"
#include "igea/stats.h"
#include "igea/normal.h"
#include "igea/eqerr.h"
#include "igea/regress.h"
#include "igea/accel.h"
#include "igea/envfun.h"
#include "igea/sim.h"
#include "igea/redund.h"
#include "igea/stability.h"
#include "igea/rls.h"
#include "igea/impact.h"
#include "igea/triad.h"
#include "igea/io.h"
#include "igea/nav.h"
#include "igea/dw.h"
#include "igea/noise.h"
#include "igea/inserr.h"
#endif
