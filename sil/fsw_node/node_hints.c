/*
 * The human hints of fsw_node's configuration errors (node_hints.h), built
 * from the configuration registry's rows, so a hint names the keys the
 * parser (node_config.c) reads.
 */
#include "node_hints.h"

#include <stdio.h>

void aocs_node_config_table_names(aocs_law_id_t law, char *buf, size_t size)
{
    size_t used = 0u;
    int i;
    buf[0] = '\0';
    for (i = 0; i < (int)AOCS_GAIN_TABLE_COUNT; ++i) {
        aocs_gain_table_id_t t = (aocs_gain_table_id_t)i;
        if ((aocs_gain_table_law(t) == law) && (used < size)) {
            int n = snprintf(buf + used, size - used, "%s%s", (used > 0u) ? ", " : "", aocs_gain_table_name(t));
            used += (n > 0) ? (size_t)n : 0u;
        }
    }
}

const aocs_config_field_t *aocs_node_config_gain_field(const aocs_config_field_t *table)
{
    uint32_t i;
    for (i = 0u; i < aocs_config_field_count(); ++i) {
        const aocs_config_field_t *f = aocs_config_field_at(i);
        if ((f->kind == AOCS_CONFIG_KIND_REALS) && (f->offset == table->offset)) {
            return f;
        }
    }
    return NULL;
}

const char *aocs_node_config_gain_keys(aocs_law_id_t law, char *buf, size_t size)
{
    uint32_t i;
    for (i = 0u; i < aocs_config_field_count(); ++i) {
        const aocs_config_field_t *t = aocs_config_field_at(i);
        const aocs_config_field_t *k = (t->kind == AOCS_CONFIG_KIND_TABLE) ? aocs_node_config_gain_field(t) : NULL;
        if ((k != NULL) && (t->law == law) && (size > 0u)) {
            (void)snprintf(buf, size, "%s / %s", k->key, t->key);
            return buf;
        }
    }
    return "the gains of the selected law";
}

/* appends text to buf (size bytes), keeping it NUL-terminated; *used grows */
static void append(char *buf, size_t size, size_t *used, const char *text)
{
    if (*used < size) {
        int n = snprintf(buf + *used, size - *used, "%s", text);
        *used += (n > 0) ? (size_t)n : 0u;
    }
}

const char *aocs_node_config_status_hint(aocs_status_t st, aocs_law_id_t law, char *buf, size_t size)
{
    size_t used = 0u;
    uint32_t i;
    if ((buf == NULL) || (size == 0u)) {
        return "";
    }
    buf[0] = '\0';
    if (st == AOCS_ERR_GAIN_TABLE_INVALID) {
        return aocs_node_config_gain_keys(law, buf, size);
    }
    if ((st == AOCS_ERR_GAIN_NOT_POSITIVE) || (st == AOCS_ERR_PARAM_NOT_FINITE)) {
        append(buf, size, &used, "the gains of the selected law");
    }
    for (i = 0u; i < aocs_config_field_count(); ++i) {
        const aocs_config_field_t *f = aocs_config_field_at(i);
        const int inertia = (f->kind == AOCS_CONFIG_KIND_INERTIA) &&
                            ((st == AOCS_ERR_INERTIA_NOT_SYMMETRIC) || (st == AOCS_ERR_INERTIA_NOT_POS_DEF) ||
                             (st == AOCS_ERR_INERTIA_SINGULAR));
        if ((st != AOCS_OK) && ((f->status == st) || (f->also == st) || inertia)) {
            append(buf, size, &used, (used > 0u) ? ", " : "");
            append(buf, size, &used, (aocs_config_field_is_per_wheel(f) != 0) ? "wheel<i>." : "");
            append(buf, size, &used, f->key);
            append(buf, size, &used, (f->help[0] != '\0') ? " (" : "");
            append(buf, size, &used, f->help);
            append(buf, size, &used, (f->help[0] != '\0') ? ")" : "");
        }
    }
    return (used > 0u) ? buf : "the keys of the selected law";
}
