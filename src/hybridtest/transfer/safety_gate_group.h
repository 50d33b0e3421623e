#pragma once
// transitional: removed after the merge of s7-sub. SafetyGateGroup is SafetyGate (n actuators).
#include "hybridtest/transfer/safety_gate.h"
