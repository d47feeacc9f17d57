/* io_obj.c: to be written. */
#include "internal.h"
