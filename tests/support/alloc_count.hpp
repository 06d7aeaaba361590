#pragma once
// "No allocation per frame at steady state", measured: linking the hullpose_test_alloc_count
// object library replaces every form of the global operator new/delete of the test executable
// with one that counts, in every thread.
namespace hullpose::test {

// Global operator new calls (all forms, all threads) since the program started.
long allocations();

}  // namespace hullpose::test
