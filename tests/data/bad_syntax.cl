/* A procedure with a syntax error on line 4, for tests/runtime/test_build_errors.c. */
void broken(perma_ctx *ctx, __local const uint *item)
{
    uint x = *item +;
}
