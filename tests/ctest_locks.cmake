# Included by CTest after the discovered cases (tests/CMakeLists.txt, TEST_INCLUDE_FILES).
# Cases that are the first, with an empty Mesa cache, to compile the same large MLP kernels
# (lavapipe compiles at the first dispatch: about 130 s for the width-64 backward) are run one
# at a time, so that the second finds them in the cache. In a CI-like run these two started
# side by side and each compiled the width-64, 3-layer kernels: 237 s and 180 s.
set_tests_properties(
  [==[bench scaling: one CSV row per setting with positive step and frame times and peak memory]==]
  [==[COLMAP dataset: a rig in COLMAP's own frame loads with up, proportions and the water height recovered]==]
  PROPERTIES RESOURCE_LOCK mlp-w64-first-compile)
