// ppti
#include "c\\\\\\\\\\\\\\\nor"cc}
