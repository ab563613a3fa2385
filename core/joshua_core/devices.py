"""Facts of the devices both the compiler and the runtime know: serial speeds of the servo bus and the lidar."""

# STS3215 baud rates and the code each is written as in the servo's baud-rate register (address 6; Feetech's
# STS memory table; codes 5-7 as feetech-servo-sdk 1.0.0 and LeRobot 0.4.4 use them).
STS3215_BAUD_RATE_CODES = {1_000_000: 0, 500_000: 1, 250_000: 2, 128_000: 3, 115_200: 4, 76_800: 5, 57_600: 6, 38_400: 7}
STS3215_BAUD_RATES = tuple(STS3215_BAUD_RATE_CODES)
STS3215_DEFAULT_BAUD_RATE = 1_000_000
# The LDS-01 lidar streams at one fixed speed.
LDS01_BAUD_RATE = 230_400
