/* io_off.c: to be written. */
#include "internal.h"
