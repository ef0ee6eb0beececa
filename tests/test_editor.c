#include "editor.h"
#include "testlib.h"

int main(void)
{
    st_doc d;
    st_doc_init(&d);
    st_error err;
    CHECK(st_doc_open(&d, STRATA_ASSETS "/cube.obj", "catmull-clark", 2, &err) == 0);
    st_doc_free(&d);
    return TEST_END();
}
