/* polarcam/usb3v.h - USB3 Vision devices seen through libusb, with a diagnosis of why one
 * cannot be used: no permission on /dev/bus/usb (udev rule), the usbfs memory limit (Linux's
 * default 16 MB is far too small for USB3 Vision streaming), a port slower than SuperSpeed. */
#ifndef POLARCAM_USB3V_H
#define POLARCAM_USB3V_H

#include <stdbool.h>
#include <stddef.h>

#include "polarcam/export.h"
#include "polarcam/source.h"

#ifdef __cplusplus
extern "C" {
#endif

/* USB3 Vision interfaces: class 0xEF (miscellaneous), subclass 0x05 (USB3 Vision). */
#define PC_USB3V_CLASS    0xEF
#define PC_USB3V_SUBCLASS 0x05

/* Link speeds (the values of libusb_speed). */
enum {
	PC_USB_SPEED_UNKNOWN = 0,
	PC_USB_SPEED_LOW,
	PC_USB_SPEED_FULL,
	PC_USB_SPEED_HIGH,
	PC_USB_SPEED_SUPER,
	PC_USB_SPEED_SUPER_PLUS
};

/* Why a device cannot be opened, as libusb_open reports it. */
enum {
	PC_USB_OPEN_OK = 0,
	PC_USB_OPEN_ACCESS,
	PC_USB_OPEN_BUSY,
	PC_USB_OPEN_GONE,
	PC_USB_OPEN_OTHER
};

/* Recommended usbfs memory for streaming (Aravis's documentation: 1000 MB for several
 * cameras); below this we warn. */
#define PC_USBFS_MIN_MB 256

/* Pure diagnosis: writes the problems found (or "") into note and returns true when the device
 * should stream. usbfs_mb < 0 means unknown. vid/pid and bus/address appear in the advice. */
PC_API bool pc_usb3v_diagnose(int speed, int open_status, long usbfs_mb, unsigned vid, unsigned pid,
                              unsigned bus, unsigned address, char *note, size_t size);

/* The usbfs memory limit in MB from /sys/module/usbcore/parameters/usbfs_memory_mb, -1 when
 * it cannot be read. */
PC_API long pc_usbfs_memory_mb(void);

/* Lists USB3 Vision devices (needs libusb: PC_ENOTSUP without). */
PC_API int pc_usb3v_list(pc_device_fn fn, void *ctx);

#ifdef __cplusplus
}
#endif
#endif
