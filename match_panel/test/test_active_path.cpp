#include <gtest/gtest.h>

#include "match_panel/active_path.h"

using match_panel::ActivePath;
using V = std::vector<std::string>;

TEST(ActivePath, RootIsTheStrategyNameUpperCase) {
  EXPECT_EQ("/MATCH_2009", ActivePath::rootFor("match_2009"));
  EXPECT_EQ("/HOMOLOGATION", ActivePath::rootFor("homologation"));
}

TEST(ActivePath, CurrentRootIsTheStrategysElseTheLastRootHeard) {
  ActivePath a;
  EXPECT_EQ("", a.currentRoot("match"));
  a.update("/HOMOLOGATION", {"BODY"}, {"BODY"});
  a.update("/HOMOLOGATION/BODY", {"A"}, {"A"});  // a child is not a root
  EXPECT_EQ("/HOMOLOGATION", a.currentRoot("homologation"));
  // match delegates to match2009, whose root is /MATCH2009: the last root heard.
  a.update("/MATCH2009", {"BODY"}, {"BODY"});
  EXPECT_EQ("/MATCH2009", a.currentRoot("match"));
  EXPECT_EQ("/HOMOLOGATION", a.currentRoot("homologation"));  // its own root wins once seen
}

TEST(ActivePath, FollowsActiveStatesIntoKnownContainers) {
  ActivePath a;
  EXPECT_EQ("", a.path("/MATCH"));  // root never seen
  a.update("/MATCH", {"BODY"}, {"BODY"});
  EXPECT_EQ("/MATCH/BODY", a.path("/MATCH"));  // BODY's container not seen yet: stops at it
  a.update("/MATCH/BODY", {"INIT"}, {"COLLECT"});
  a.update("/MATCH/BODY/COLLECT", {"GO"}, {"GRAB"});
  EXPECT_EQ("/MATCH/BODY/COLLECT/GRAB", a.path("/MATCH"));
  a.update("/MATCH/BODY", {"INIT"}, {"SCORE"});  // another branch, whose container is unknown
  EXPECT_EQ("/MATCH/BODY/SCORE", a.path("/MATCH"));
}

TEST(ActivePath, TerminatedContainerEndsThePath) {
  ActivePath a;
  a.update("/M", {"BODY"}, {"BODY"});
  a.update("/M/BODY", {"A"}, {});
  EXPECT_EQ("/M/BODY", a.path("/M"));
  a.update("/M", {"BODY"}, {});
  EXPECT_EQ("/M", a.path("/M"));
}

TEST(ActivePath, LastTriggerIsTheRootsLastNonBodyStateAndStays) {
  ActivePath a;
  a.update("/M", {"BODY"}, {"BODY"});
  EXPECT_EQ("", a.lastTrigger("/M"));
  a.update("/M", {"BODY"}, {"OBSTACLE"});
  EXPECT_EQ("OBSTACLE", a.lastTrigger("/M"));
  EXPECT_EQ("/M/OBSTACLE", a.path("/M"));
  a.update("/M", {"BODY"}, {"BODY"});
  EXPECT_EQ("OBSTACLE", a.lastTrigger("/M"));  // kept after its handler returned to BODY
  a.update("/M", {"BODY"}, {"TIMEOUT"});
  EXPECT_EQ("TIMEOUT", a.lastTrigger("/M"));
}

TEST(ActivePath, PlainStateMachineRootHasNoTriggers) {
  // A strategy without triggers: its root is the state machine itself.
  ActivePath a;
  a.update("/EXAMPLE", {"START"}, {"MOVE"});
  EXPECT_EQ("", a.lastTrigger("/EXAMPLE"));
  EXPECT_EQ("/EXAMPLE/MOVE", a.path("/EXAMPLE"));
}

TEST(ActivePath, NestedContainersDoNotCountAsTriggers) {
  ActivePath a;
  a.update("/M", {"BODY"}, {"BODY"});
  a.update("/M/BODY", {"A"}, {"B"});
  EXPECT_EQ("", a.lastTrigger("/M"));
}
