// SerialPort (termios) on a real pty: raw bytes through, hang-up detected, reopen works.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>

#include "hcl_drivers/transport/serial_port.h"

using hcl_drivers::transport::SerialPort;

TEST(SerialPort, RawBytesThroughAPtyAndHangUpClosesThePort) {
  const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
  ASSERT_GE(master, 0);
  ASSERT_EQ(::grantpt(master), 0);
  ASSERT_EQ(::unlockpt(master), 0);
  SerialPort port(::ptsname(master), 9600);
  std::string err;
  ASSERT_TRUE(port.open(err)) << err;
  // Raw mode: CR, LF and control bytes arrive unchanged.
  const uint8_t out[] = {'$', 'B', '\r', '\n', 0x03, 0x7F};
  ASSERT_EQ(::write(master, out, sizeof(out)), static_cast<ssize_t>(sizeof(out)));
  uint8_t in[16];
  std::size_t got = 0;
  for (int i = 0; i < 20 && got < sizeof(out); ++i) {
    const long n = port.read(in + got, sizeof(in) - got, 0.1, err);
    ASSERT_GE(n, 0) << err;
    got += static_cast<std::size_t>(n);
  }
  ASSERT_EQ(got, sizeof(out));
  EXPECT_EQ(0, std::memcmp(in, out, sizeof(out)));
  EXPECT_EQ(port.read(in, sizeof(in), 0.02, err), 0);  // timeout, nothing more
  ::close(master);
  EXPECT_EQ(port.read(in, sizeof(in), 0.5, err), -1);
  EXPECT_FALSE(port.isOpen());
  EXPECT_FALSE(port.open(err));  // the pty is gone
}

TEST(SerialPort, BaudRates) {
  EXPECT_EQ(SerialPort::baudConstant(9600), static_cast<speed_t>(B9600));
  EXPECT_EQ(SerialPort::baudConstant(115200), static_cast<speed_t>(B115200));
  EXPECT_EQ(SerialPort::baudConstant(9601), 0u);
  SerialPort missing("/tmp/no_such_tty_for_test", 9600);
  std::string err;
  EXPECT_FALSE(missing.open(err));
  EXPECT_NE(err.find("/tmp/no_such_tty_for_test"), std::string::npos);
}
