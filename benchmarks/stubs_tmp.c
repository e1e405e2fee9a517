#include "bench.h"
int bench_queue(const bench_options *o, int argc, char **argv) { (void)o; (void)argc; (void)argv; return 0; }
int bench_pipeline(const bench_options *o, int argc, char **argv) { (void)o; (void)argc; (void)argv; return 0; }
