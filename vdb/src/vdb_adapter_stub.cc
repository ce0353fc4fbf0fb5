// Placeholder so the adapter target has a source until vdb_read.cc lands.
#include "vbl_vdb_adapter.h"
