// AFL-style edge coverage for any GCC front end (gfortran included): a minimal GCC plugin.
//
// Why it exists: Debian bookworm's afl++ ships afl-gcc-pass.so, but it was built against an
// earlier gcc-12 package and refuses the installed compiler ("GCC and plugin have incompatible
// versions"). This plugin is compiled on the spot against the installed gcc-12-plugin-dev, so
// it always matches. It counts, in AFL's shared map (__afl_area_ptr of afl-compiler-rt.o,
// which also provides the fork server), every CFG edge of every instrumented function:
//   - a block with a single predecessor gets one counter at its start;
//   - a block with several predecessors gets one counter per incoming edge, on the edge itself
//     (GCC splits the edge where needed), so "which branch led here" is recorded.
// The slot of a counter is a hash of the function's assembler name and the edge, so a rebuild
// gives the same map. Usage:
//   g++ -shared -fPIC -fno-rtti -I$(gcc -print-file-name=plugin)/include afl_gcc_cov.cc -o x.so
//   gfortran -fplugin=./x.so ... ; link with /usr/lib/afl/afl-compiler-rt.o
#include "gcc-plugin.h"
#include "plugin-version.h"
#include "tree.h"
#include "tree-pass.h"
#include "context.h"
#include "function.h"
#include "basic-block.h"
#include "cfg.h"
#include "gimple.h"
#include "gimple-iterator.h"
#include "gimplify.h"
#include "stringpool.h"
#include "diagnostic-core.h"

int plugin_is_GPL_compatible;

namespace {

const unsigned map_size = 1u << 16;  // MAP_SIZE of afl-compiler-rt.o

tree area_ptr_decl = NULL_TREE;

// extern unsigned char *__afl_area_ptr;
tree area_ptr() {
    if (area_ptr_decl == NULL_TREE) {
        tree type = build_pointer_type(unsigned_char_type_node);
        area_ptr_decl = build_decl(UNKNOWN_LOCATION, VAR_DECL,
                                   get_identifier("__afl_area_ptr"), type);
        TREE_PUBLIC(area_ptr_decl) = 1;
        DECL_EXTERNAL(area_ptr_decl) = 1;
        DECL_ARTIFICIAL(area_ptr_decl) = 1;
        TREE_USED(area_ptr_decl) = 1;
    }
    return area_ptr_decl;
}

// FNV-1a of the function name and the edge (source and destination block indices).
unsigned slot(const char *name, int from, int to) {
    unsigned h = 2166136261u;
    for (const char *c = name; *c; ++c) h = (h ^ (unsigned char)*c) * 16777619u;
    h = (h ^ (unsigned)from) * 16777619u;
    h = (h ^ (unsigned)to) * 16777619u;
    return (h ^ (h >> 16)) % map_size;
}

// __afl_area_ptr[idx]++, as GIMPLE on temporaries (the pass runs before the SSA form).
gimple_seq counter(unsigned idx) {
    gimple_seq seq = NULL;
    tree uchar = unsigned_char_type_node;
    tree ptr_type = build_pointer_type(uchar);
    tree base = create_tmp_var(ptr_type, "afl_area");
    gimple_seq_add_stmt(&seq, gimple_build_assign(base, area_ptr()));
    tree addr = create_tmp_var(ptr_type, "afl_slot");
    gimple_seq_add_stmt(&seq, gimple_build_assign(addr, POINTER_PLUS_EXPR, base,
                                                  size_int(idx)));
    tree old_count = create_tmp_var(uchar, "afl_count");
    gimple_seq_add_stmt(&seq, gimple_build_assign(old_count,
        build2(MEM_REF, uchar, addr, build_int_cst(ptr_type, 0))));
    tree new_count = create_tmp_var(uchar, "afl_count");
    gimple_seq_add_stmt(&seq, gimple_build_assign(new_count, PLUS_EXPR, old_count,
                                                  build_int_cst(uchar, 1)));
    gimple_seq_add_stmt(&seq, gimple_build_assign(
        build2(MEM_REF, uchar, addr, build_int_cst(ptr_type, 0)), new_count));
    return seq;
}

const pass_data cov_pass_data = {
    GIMPLE_PASS, "afl_cov", OPTGROUP_NONE, TV_NONE,
    PROP_cfg, 0, 0, 0, 0,
};

struct cov_pass : gimple_opt_pass {
    explicit cov_pass(gcc::context *ctx) : gimple_opt_pass(cov_pass_data, ctx) {}

    unsigned int execute(function *fun) final override {
        const char *name = IDENTIFIER_POINTER(DECL_ASSEMBLER_NAME(fun->decl));
        basic_block bb;
        bool on_edges = false;
        FOR_EACH_BB_FN(bb, fun) {
            bool split = EDGE_COUNT(bb->preds) > 1;
            edge e;
            edge_iterator ei;
            FOR_EACH_EDGE(e, ei, bb->preds) {
                if (e->flags & EDGE_COMPLEX) split = false;
            }
            if (split) {
                FOR_EACH_EDGE(e, ei, bb->preds) {
                    gsi_insert_seq_on_edge(e, counter(slot(name, e->src->index, bb->index)));
                }
                on_edges = true;
            } else {
                gimple_stmt_iterator gsi = gsi_after_labels(bb);
                gsi_insert_seq_before(&gsi, counter(slot(name, -1, bb->index)),
                                      GSI_SAME_STMT);
            }
        }
        if (on_edges) gsi_commit_edge_inserts();
        return 0;
    }
};

}  // namespace

int plugin_init(struct plugin_name_args *info, struct plugin_gcc_version *version) {
    if (!plugin_default_version_check(version, &gcc_version)) {
        error("%s: built for GCC %s, this is GCC %s: rebuild the plugin", info->base_name,
              gcc_version.basever, version->basever);
        return 1;
    }
    // after the CFG is built, before the SSA form: plain temporaries are enough
    struct register_pass_info pass;
    pass.pass = new cov_pass(g);
    pass.reference_pass_name = "cfg";
    pass.ref_pass_instance_number = 1;
    pass.pos_op = PASS_POS_INSERT_AFTER;
    register_callback(info->base_name, PLUGIN_PASS_MANAGER_SETUP, NULL, &pass);
    return 0;
}
