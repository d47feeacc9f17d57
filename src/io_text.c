/* io_text.c: to be written. */
#include "internal.h"
