// Register maps of the I2C parts: decoding of what the chips answer, encoding of what we write.
#include <gtest/gtest.h>

#include "hcl_drivers/boards/cmps03_registers.h"
#include "hcl_drivers/boards/hbmotor_registers.h"
#include "hcl_drivers/boards/mcp23016_registers.h"
#include "hcl_drivers/boards/srf02_registers.h"
#include "hcl_drivers/transport/i2c_dev_bus.h"

using namespace hcl_drivers;

TEST(HBMotorRegisters, DecodesTheNineByteBlock) {
  const std::vector<uint8_t> raw = {0x12, 0x81, 0xF6, 0x00, 0x78, 0x56, 0x34, 0x12, 25};
  const auto b = hbmotor::decodeBlock(raw);
  ASSERT_TRUE(b);
  EXPECT_EQ(b->version, 0x12);
  EXPECT_EQ(b->status, 0x81);
  EXPECT_EQ(b->command, -10);
  EXPECT_EQ(b->encoder, 0x12345678u);
  EXPECT_EQ(b->watchdog, 25);
}

TEST(HBMotorRegisters, RejectsWrongSizeAndReservedBits) {
  EXPECT_FALSE(hbmotor::decodeBlock({0x12, 0x00, 0, 0, 0, 0, 0, 0}));
  EXPECT_FALSE(hbmotor::decodeBlock({0x12, 0x08, 0, 0, 0, 0, 0, 0, 0}));
  EXPECT_FALSE(hbmotor::decodeBlock({0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF}));  // floating bus
}

TEST(HBMotorRegisters, CommandIsClampedToSymmetricRange) {
  EXPECT_EQ(hbmotor::encodeCommand(0), 0);
  EXPECT_EQ(hbmotor::encodeCommand(100), 100);
  EXPECT_EQ(static_cast<int8_t>(hbmotor::encodeCommand(-100)), -100);
  EXPECT_EQ(hbmotor::encodeCommand(1000), 127);
  EXPECT_EQ(static_cast<int8_t>(hbmotor::encodeCommand(-1000)), -127);  // never -128
}

TEST(HBMotorRegisters, WatchdogInTenMillisecondTicks) {
  EXPECT_EQ(hbmotor::encodeWatchdog(0.0), 0);
  EXPECT_EQ(hbmotor::encodeWatchdog(0.25), 25);
  EXPECT_EQ(hbmotor::encodeWatchdog(0.001), 1);
  EXPECT_EQ(hbmotor::encodeWatchdog(10.0), 255);
}

TEST(MCP23016Registers, PairsArePortZeroFirst) {
  EXPECT_EQ(mcp23016::encodePair(0xA55A), (std::vector<uint8_t>{0x5A, 0xA5}));
  EXPECT_EQ(mcp23016::decodePair({0x5A, 0xA5}), 0xA55A);
  EXPECT_EQ(mcp23016::inputBits(0xFFFF, 0x00FF), 0x00FF);
  EXPECT_EQ(mcp23016::kRegIodir0, 0x06);
  EXPECT_EQ(mcp23016::kRegIpol0, 0x04);
  EXPECT_EQ(mcp23016::kRegOlat0, 0x02);
}

TEST(SRF02Registers, BusyWhileRangingThenCentimetres) {
  EXPECT_EQ(srf02::decodeResult({0xFF, 0xFF, 0xFF, 0xFF}).kind, srf02::ResultKind::kBusy);
  const auto r = srf02::decodeResult({0x06, 0x80, 0x01, 0x2C});
  EXPECT_EQ(r.kind, srf02::ResultKind::kRange);
  EXPECT_EQ(r.range_cm, 300);
  EXPECT_DOUBLE_EQ(srf02::centimetresToMetres(r.range_cm), 3.0);
  EXPECT_EQ(srf02::decodeResult({0x06, 0x80, 0x10, 0x00}).kind, srf02::ResultKind::kInvalid);  // 4096 cm
  EXPECT_EQ(srf02::decodeResult({0x06, 0x80}).kind, srf02::ResultKind::kInvalid);
  EXPECT_EQ(srf02::kCmdRangeCm, 0x51);
}

TEST(CMPS03Registers, WordBearingInTenthsOfDegrees) {
  // 359.9 deg: word 3599 = 0x0E0F, byte 255.
  auto r = cmps03::decodeBlock({0x0E, 255, 0x0E, 0x0F});
  ASSERT_TRUE(r);
  EXPECT_NEAR(r->degrees(), 359.9, 1e-9);
  r = cmps03::decodeBlock({0x0E, 64, 0x03, 0x84});  // 90.0 deg
  ASSERT_TRUE(r);
  EXPECT_NEAR(r->degrees(), 90.0, 1e-9);
  r = cmps03::decodeBlock({0x0E, 0, 0x00, 0x00});
  ASSERT_TRUE(r);
  EXPECT_EQ(r->degrees(), 0.0);
  r = cmps03::decodeBlock({0x0E, 255, 0x00, 0x02});  // 0.2 deg vs byte 255: agree across north
  EXPECT_TRUE(r);
}

TEST(CMPS03Registers, RejectsOutOfRangeAndDisagreement) {
  EXPECT_FALSE(cmps03::decodeBlock({0x0E, 0, 0x0E, 0x10}));  // 3600
  EXPECT_FALSE(cmps03::decodeBlock({0x0E, 128, 0x03, 0x84}));  // byte says 180, word says 90
  EXPECT_FALSE(cmps03::decodeBlock({0x0E, 0, 0x00}));
}

TEST(I2cDevBus, ErrnoMapsToStatus) {
  using transport::I2cDevBus;
  using transport::I2cStatus;
  EXPECT_EQ(I2cDevBus::statusFromErrno(ENXIO), I2cStatus::kNack);
  EXPECT_EQ(I2cDevBus::statusFromErrno(EREMOTEIO), I2cStatus::kNack);
  EXPECT_EQ(I2cDevBus::statusFromErrno(ETIMEDOUT), I2cStatus::kTimeout);
  EXPECT_EQ(I2cDevBus::statusFromErrno(EIO), I2cStatus::kBusError);
  EXPECT_EQ(I2cDevBus::statusFromErrno(EAGAIN), I2cStatus::kBusError);
}

TEST(I2cDevBus, MissingDeviceIsAClearError) {
  try {
    transport::openI2cBus("/dev/i2c-250");
    FAIL() << "opened a missing device";
  } catch (const std::system_error& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/i2c-250"), std::string::npos) << e.what();
  }
  EXPECT_THROW(transport::openI2cBus("udp://1.2.3.4:5"), std::invalid_argument);
}
