# CTest include file (runs after gtest_discover_tests' own): the label "timing" on the core tests whose subject is
# threads, aborts, budgets or progressive frames, so that they can be run many times under CPU load
# (ctest -L timing; see README "Tests"). Their verdicts must not depend on scheduling.
foreach(test
    Renderer.BitIdenticalForAnyThreadCount
    Renderer.AbortThenRenderAgainGivesTheRightImage
    Renderer.AllCoresMeansTheAffinityMask
    Renderer.ProgressIsMonotonicOnCallerAndReachesOne
    Renderer.ExceptionInFrameIsRethrownAfterJoin
    ErrorEstimate.TargetErrorStopsRefiningWhenMet
    ErrorEstimate.TimeBudgetHonouredWithinOneTile
    ErrorEstimate.RefinementContinuesAcrossCalls
    ErrorEstimate.RoundCutShortIsFinishedByTheNextCall
    Scene.BackgroundUpgradeSwapsInTheSahTreeOnceBuilt
    Scene.BackgroundUpgradeLandsWhileFramesKeepComing
    Scene.BackgroundUpgradeRestartsWhereItsPriorityCannotBeRaised
    Scene.BackgroundUpgradeOfReplacedGeometryIsDropped
    Bvh.ParallelBuildKeepsInvariantsAndIsDeterministic
    Bvh.ParallelBuildOfSinglePrimitiveLeaves
    Bvh.CancelledBuildLeavesAnEmptyTree
    ThreadPool.EveryJobRunsOnceOnAtMostTheRequestedThreads
    ThreadPool.JobExceptionIsRethrownAfterEveryJobRan
    ThreadPool.NestedUseDoesNotDeadlock
    ThreadPool.ConcurrentUseFromTwoThreads)
  set_tests_properties(${test} PROPERTIES LABELS "core;timing")
endforeach()
