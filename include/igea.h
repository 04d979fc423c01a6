/* igea.h - umbrella header: every public igea header. */
#ifndef IGEA_H
#define IGEA_H
#include "igea/common.h"
#include "igea/stats.h"
#include "igea/normal.h"
#include "igea/eqerr.h"
#endif
