/* The test library's own verdicts (testlib.h): a test that checks nothing
 * fails, a skipped part turns a pass into a skip (77, ctest's
 * SKIP_RETURN_CODE), a failure wins over both. */
#include "testlib.h"

static int verdict(int passed, int failed, int skipped)
{
    int p = tl_passed, f = tl_failed, s = tl_skipped;
    tl_passed = passed;
    tl_failed = failed;
    tl_skipped = skipped;
    int rc = tl_report("(verdict)");
    tl_passed = p;
    tl_failed = f;
    tl_skipped = s;
    return rc;
}

int main(void)
{
    CHECK(verdict(0, 0, 0) == 1);
    CHECK(verdict(3, 0, 0) == 0);
    CHECK(verdict(3, 1, 0) == 1);
    CHECK(verdict(3, 0, 1) == TL_SKIP_CODE);
    CHECK(verdict(0, 0, 1) == TL_SKIP_CODE);
    CHECK(verdict(3, 1, 1) == 1);
    CHECK(verdict(0, 1, 0) == 1);
    CHECK(TL_SKIP_CODE == 77);
    int before = tl_skipped;
    tl_skip("a part of this test (%s)", "counted");
    CHECK(tl_skipped == before + 1);
    tl_skipped = before;
    return TEST_END();
}
