/*
 * config.c — the environment's settings, read once (config.h).
 */
#include "config.h"

#include <stdlib.h>

/* $name, NULL when unset or empty (an empty setting is no setting). */
static const char *config_get(const char *name)
{
    const char *v = getenv(name);
    return v && *v ? v : NULL;
}

void config_read(csg_config *c)
{
#define CONFIG_GET(field, name, what) c->field = config_get(name);
    CONFIG_VARIABLES(CONFIG_GET)
#undef CONFIG_GET
    c->xdg_cache_home = config_get("XDG_CACHE_HOME");
    c->home = config_get("HOME");
}

void config_usage(FILE *out)
{
    fputs("environment:\n", out);
#define CONFIG_LINE(field, name, what) fprintf(out, "  %-23s %s\n", name, what);
    CONFIG_VARIABLES(CONFIG_LINE)
#undef CONFIG_LINE
}
