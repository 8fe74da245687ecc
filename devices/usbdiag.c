#include "polarcam/usb3v.h"

#include <stdio.h>
#include <string.h>

static void add(char *note, size_t size, const char *text)
{
	size_t len = strlen(note);
	if (len + 3 < size)
		snprintf(note + len, size - len, "%s%s", len ? "; " : "", text);
}

bool pc_usb3v_diagnose(int speed, int open_status, long usbfs_mb, unsigned vid, unsigned pid,
                       unsigned bus, unsigned address, char *note, size_t size)
{
	char buf[320];
	bool ok = true;
	if (!note || !size)
		return false;
	note[0] = '\0';
	switch (open_status) {
	case PC_USB_OPEN_OK:
		break;
	case PC_USB_OPEN_ACCESS:
		snprintf(buf, sizeof buf,
		         "no permission to open /dev/bus/usb/%03u/%03u: add a udev rule such as "
		         "SUBSYSTEM==\"usb\", ATTR{idVendor}==\"%04x\", ATTR{idProduct}==\"%04x\", "
		         "MODE=\"0660\", GROUP=\"plugdev\" (or TAG+=\"uaccess\") in "
		         "/etc/udev/rules.d/, then replug",
		         bus, address, vid, pid);
		add(note, size, buf);
		ok = false;
		break;
	case PC_USB_OPEN_BUSY:
		add(note, size, "the device is claimed by another program or driver");
		ok = false;
		break;
	case PC_USB_OPEN_GONE:
		add(note, size, "the device disappeared while being examined");
		ok = false;
		break;
	default:
		add(note, size, "the device cannot be opened");
		ok = false;
		break;
	}
	if (speed != PC_USB_SPEED_UNKNOWN && speed < PC_USB_SPEED_SUPER) {
		snprintf(
		    buf, sizeof buf,
		    "connected at %s speed, not SuperSpeed: plug it into a USB 3 port with a USB 3 "
		    "cable (USB3 Vision needs SuperSpeed for full frame rates)",
		    speed == PC_USB_SPEED_HIGH   ? "high (480 Mb/s)"
		    : speed == PC_USB_SPEED_FULL ? "full (12 Mb/s)"
		                                 : "low (1.5 Mb/s)");
		add(note, size, buf);
		ok = false;
	}
	if (usbfs_mb >= 0 && usbfs_mb < PC_USBFS_MIN_MB) {
		snprintf(buf, sizeof buf,
		         "usbfs memory limit is %ld MB: streaming needs more (echo 1000 > "
		         "/sys/module/usbcore/parameters/usbfs_memory_mb, or "
		         "usbcore.usbfs_memory_mb=1000 "
		         "on the kernel command line)",
		         usbfs_mb);
		add(note, size, buf);
		ok = false;
	}
	return ok;
}

long pc_usbfs_memory_mb(void)
{
	FILE *fp = fopen("/sys/module/usbcore/parameters/usbfs_memory_mb", "r");
	if (!fp)
		return -1;
	long v = -1;
	if (fscanf(fp, "%ld", &v) != 1)
		v = -1;
	fclose(fp);
	return v;
}
