// Frame encoding/decoding of every CAN board, byte-exact against each board's documentation,
// and the conversions the drivers own (GP2D12 curve, DS-402 state machine, LCD lines).
#include <gtest/gtest.h>

#include <cmath>

#include "epos_protocol.h"
#include "hmi_board_protocol.h"
#include "motor_board_protocol.h"
#include "servo_board_protocol.h"
#include "stepper_board_protocol.h"

using namespace hcl_drivers;
using transport::CanFrame;

namespace {
std::vector<uint8_t> bytes(const CanFrame& f) { return std::vector<uint8_t>(f.data.begin(), f.data.begin() + f.dlc); }
}  // namespace

TEST(MotorBoard, CommandAndTelemetry) {
  const CanFrame c = motor_board::encodeCommand(0x20A, {-1000, 500});
  EXPECT_EQ(c.id, 0x20Au);
  EXPECT_EQ(bytes(c), (std::vector<uint8_t>{0x18, 0xFC, 0xF4, 0x01}));
  EXPECT_EQ(bytes(motor_board::encodeCommand(0x20A, {30000, -30000})), (std::vector<uint8_t>{0xE8, 0x03, 0x18, 0xFC}))
      << "clamped to +-1000";
  const auto e = motor_board::decodeEncoders(CanFrame::make(0x18A, {0x01, 0, 0, 0, 0xFF, 0xFF, 0xFF, 0xFF}));
  ASSERT_TRUE(e);
  EXPECT_EQ(e->raw[0], 1u);
  EXPECT_EQ(e->raw[1], 0xFFFFFFFFu);
  EXPECT_FALSE(motor_board::decodeEncoders(CanFrame::make(0x18A, {1, 2, 3})));
  EXPECT_FALSE(motor_board::decodeEncoders(CanFrame::remote(0x18A, 8)));
  const auto s = motor_board::decodeStatus(CanFrame::make(0x28A, {0x18, 0xFC, 0, 0, 0x01}));
  ASSERT_TRUE(s);
  EXPECT_EQ(s->pwm[0], -1000);
  EXPECT_TRUE(s->watchdog_stopped);
  EXPECT_FALSE(motor_board::decodeStatus(CanFrame::make(0x28A, {0xE9, 0x03, 0, 0, 0})))  << "1001 is out of range";
  EXPECT_FALSE(motor_board::decodeStatus(CanFrame::make(0x28A, {0, 0, 0, 0, 0x02}))) << "reserved flag bits";
  EXPECT_FALSE(motor_board::decodeStatus(CanFrame::make(0x28A, {0, 0, 0, 0})));
}

TEST(StepperBoard, TargetsPositionsSwitches) {
  EXPECT_EQ(bytes(stepper_board::encodeTargets(0x20B, {-2, 70000})),
            (std::vector<uint8_t>{0xFE, 0xFF, 0xFF, 0xFF, 0x70, 0x11, 0x01, 0x00}));
  const auto p = stepper_board::decodePositions(CanFrame::make(0x18B, {0xFE, 0xFF, 0xFF, 0xFF, 0x70, 0x11, 0x01, 0x00}));
  ASSERT_TRUE(p);
  EXPECT_EQ((*p)[0], -2);
  EXPECT_EQ((*p)[1], 70000);
  const auto s = stepper_board::decodeSwitches(CanFrame::make(0x28B, {0x09, 0x02}));
  ASSERT_TRUE(s);
  EXPECT_EQ(s->end_switches, 0x09);
  EXPECT_EQ(s->moving, 0x02);
  EXPECT_FALSE(stepper_board::decodeSwitches(CanFrame::make(0x28B, {0x10, 0})));
  EXPECT_FALSE(stepper_board::decodeSwitches(CanFrame::make(0x28B, {0, 0x04})));
  EXPECT_FALSE(stepper_board::decodePositions(CanFrame::make(0x18B, {0, 0, 0, 0})));
}

TEST(ServoBoard, ServosRangersSwitches) {
  EXPECT_EQ(bytes(servo_board::encodeServos(0x20C, {1500, 0, 500, 2500})),
            (std::vector<uint8_t>{0xDC, 0x05, 0, 0, 0xF4, 0x01, 0xC4, 0x09}));
  EXPECT_TRUE(servo_board::validPulse(0));
  EXPECT_TRUE(servo_board::validPulse(2500));
  EXPECT_FALSE(servo_board::validPulse(499));
  EXPECT_FALSE(servo_board::validPulse(2501));
  const auto a = servo_board::decodeRangers(CanFrame::make(0x18C, {0xFF, 0x03, 0, 0, 1, 0, 0x88, 0x01}));
  ASSERT_TRUE(a);
  EXPECT_EQ((*a)[0], 1023);
  EXPECT_EQ((*a)[3], 392);
  EXPECT_FALSE(servo_board::decodeRangers(CanFrame::make(0x18C, {0x00, 0x04, 0, 0, 0, 0, 0, 0}))) << "ADC is 10-bit";
  EXPECT_EQ(*servo_board::decodeSwitches(CanFrame::make(0x28C, {0x21, 0x80})), 0x8021);
  EXPECT_FALSE(servo_board::decodeSwitches(CanFrame::make(0x28C, {0x21})));
}

TEST(ServoBoard, Gp2d12CurveFollowsTheDatasheet) {
  auto adc = [](double volts) { return static_cast<uint16_t>(std::lround(volts / 5.0 * 1023.0)); };
  EXPECT_NEAR(servo_board::gp2d12Metres(adc(1.30)), 0.20, 0.005);
  EXPECT_NEAR(servo_board::gp2d12Metres(adc(0.92)), 0.30, 0.01);
  EXPECT_NEAR(servo_board::gp2d12Metres(adc(0.60)), 0.50, 0.02);
  EXPECT_NEAR(servo_board::gp2d12Metres(adc(2.40)), 0.10, 0.005);
  EXPECT_NEAR(servo_board::gp2d12Metres(adc(0.825)), 0.35, 0.01) << "interpolated between 30 and 40 cm";
  EXPECT_TRUE(std::isinf(servo_board::gp2d12Metres(adc(0.2))) && servo_board::gp2d12Metres(adc(0.2)) > 0);
  EXPECT_TRUE(std::isinf(servo_board::gp2d12Metres(adc(3.0))) && servo_board::gp2d12Metres(adc(3.0)) < 0);
  double last = 0.0;
  for (int raw = adc(2.4); raw >= adc(0.4); --raw) {  // monotonic: less voltage, farther
    const double d = servo_board::gp2d12Metres(static_cast<uint16_t>(raw));
    EXPECT_GE(d, last - 1e-9);
    last = d;
  }
}

TEST(Epos, CommandStatusFeedback) {
  EXPECT_EQ(bytes(epos::encodeCommand(0x201, 0x000F, -1500)), (std::vector<uint8_t>{0x0F, 0x00, 0x24, 0xFA, 0xFF, 0xFF}));
  const auto s = epos::decodeStatus(CanFrame::make(0x181, {0x37, 0x02, 0x03, 0x10, 0x32}));
  ASSERT_TRUE(s);
  EXPECT_EQ(s->statusword, 0x0237);
  EXPECT_EQ(s->mode_display, 3);
  EXPECT_EQ(s->error_code, 0x3210);
  const auto f = epos::decodeFeedback(CanFrame::make(0x381, {0x10, 0, 0, 0, 0x9C, 0xFF, 0xFF, 0xFF}));
  ASSERT_TRUE(f);
  EXPECT_EQ(f->position, 16);
  EXPECT_EQ(f->velocity_rpm, -100);
  EXPECT_FALSE(epos::decodeStatus(CanFrame::make(0x181, {0x37, 0x02})));
  EXPECT_FALSE(epos::decodeFeedback(CanFrame::make(0x381, {0x10, 0, 0, 0})));
}

TEST(Epos, Ds402StatesAndEnableSequence) {
  using epos::DriveState;
  EXPECT_EQ(epos::decodeDriveState(0x0240), DriveState::kSwitchOnDisabled);
  EXPECT_EQ(epos::decodeDriveState(0x0221), DriveState::kReadyToSwitchOn);
  EXPECT_EQ(epos::decodeDriveState(0x0233), DriveState::kSwitchedOn);
  EXPECT_EQ(epos::decodeDriveState(0x0237), DriveState::kOperationEnabled);
  EXPECT_EQ(epos::decodeDriveState(0x0217), DriveState::kQuickStop);
  EXPECT_EQ(epos::decodeDriveState(0x020F), DriveState::kFaultReaction);
  EXPECT_EQ(epos::decodeDriveState(0x0208), DriveState::kFault);
  EXPECT_EQ(epos::decodeDriveState(0x0000), DriveState::kNotReady);
  EXPECT_EQ(epos::nextControlword(DriveState::kSwitchOnDisabled, true), 0x0006);
  EXPECT_EQ(epos::nextControlword(DriveState::kReadyToSwitchOn, true), 0x0007);
  EXPECT_EQ(epos::nextControlword(DriveState::kSwitchedOn, true), 0x000F);
  EXPECT_EQ(epos::nextControlword(DriveState::kOperationEnabled, true), 0x000F);
  EXPECT_EQ(epos::nextControlword(DriveState::kOperationEnabled, false), 0x0006);
  EXPECT_EQ(epos::nextControlword(DriveState::kFault, true), 0x0000) << "never an automatic fault reset";
}

TEST(HmiBoard, LcdChunksAndKeys) {
  const CanFrame f = hmi_board::encodeLcd(0x20D, 1, 6, "Hello!!!");
  EXPECT_EQ(bytes(f), (std::vector<uint8_t>{1, 6, 'H', 'e', 'l', 'l', 'o', '!'})) << "6 characters per frame";
  EXPECT_EQ(hmi_board::lcdLine("abc"), "abc             ");
  EXPECT_EQ(hmi_board::lcdLine("0123456789abcdefXYZ"), "0123456789abcdef");
  EXPECT_EQ(hmi_board::lcdLine("a\tb"), "a?b             ");
  const auto k = hmi_board::decodeKeys(CanFrame::make(0x18D, {0x01, 0x80, 15, 42}));
  ASSERT_TRUE(k);
  EXPECT_EQ(k->held, 0x8001);
  EXPECT_EQ(k->last_key, 15);
  EXPECT_EQ(k->presses, 42);
  EXPECT_TRUE(hmi_board::decodeKeys(CanFrame::make(0x18D, {0, 0, 255, 0})));
  EXPECT_FALSE(hmi_board::decodeKeys(CanFrame::make(0x18D, {0, 0, 16, 0})));
  EXPECT_FALSE(hmi_board::decodeKeys(CanFrame::make(0x18D, {0, 0, 1})));
}
