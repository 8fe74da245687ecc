/* USB3 Vision devices through libusb (polarcam/usb3v.h). */
#include "polarcam/error.h"
#include "polarcam/usb3v.h"

#include <libusb.h>
#include <stdio.h>
#include <string.h>

#include "backends.h"

static bool has_usb3v_interface(libusb_device *dev)
{
	struct libusb_config_descriptor *cfg = NULL;
	if (libusb_get_active_config_descriptor(dev, &cfg) != 0 &&
	    libusb_get_config_descriptor(dev, 0, &cfg) != 0)
		return false;
	bool found = false;
	for (int i = 0; i < cfg->bNumInterfaces && !found; i++)
		for (int k = 0; k < cfg->interface[i].num_altsetting && !found; k++) {
			const struct libusb_interface_descriptor *d =
			    &cfg->interface[i].altsetting[k];
			found = d->bInterfaceClass == PC_USB3V_CLASS &&
			        d->bInterfaceSubClass == PC_USB3V_SUBCLASS;
		}
	libusb_free_config_descriptor(cfg);
	return found;
}

static int open_status(int err)
{
	switch (err) {
	case 0:
		return PC_USB_OPEN_OK;
	case LIBUSB_ERROR_ACCESS:
		return PC_USB_OPEN_ACCESS;
	case LIBUSB_ERROR_BUSY:
		return PC_USB_OPEN_BUSY;
	case LIBUSB_ERROR_NO_DEVICE:
		return PC_USB_OPEN_GONE;
	default:
		return PC_USB_OPEN_OTHER;
	}
}

int pc_usb3v_enumerate(pc_device_fn fn, void *ctx)
{
	libusb_context *lc = NULL;
	int e = libusb_init(&lc);
	if (e)
		return pc_error(PC_EIO, "libusb: %s", libusb_strerror(e));
	libusb_device **list = NULL;
	ssize_t n = libusb_get_device_list(lc, &list);
	if (n < 0) {
		libusb_exit(lc);
		return pc_error(PC_EIO, "libusb: listing devices: %s", libusb_strerror((int)n));
	}
	long usbfs = pc_usbfs_memory_mb();
	int rc = 0;
	for (ssize_t i = 0; i < n; i++) {
		libusb_device *dev = list[i];
		struct libusb_device_descriptor dd;
		if (libusb_get_device_descriptor(dev, &dd) != 0 || !has_usb3v_interface(dev))
			continue;
		pc_device_entry ent;
		memset(&ent, 0, sizeof ent);
		unsigned bus = libusb_get_bus_number(dev), addr = libusb_get_device_address(dev);
		snprintf(ent.transport, sizeof ent.transport, "USB3 Vision");
		snprintf(ent.address, sizeof ent.address, "/dev/bus/usb/%03u/%03u", bus, addr);
		snprintf(ent.vendor, sizeof ent.vendor, "%04x", dd.idVendor);
		snprintf(ent.model, sizeof ent.model, "%04x", dd.idProduct);
		libusb_device_handle *h = NULL;
		int oe = libusb_open(dev, &h);
		if (h) {
			unsigned char s[64];
			if (dd.iManufacturer && libusb_get_string_descriptor_ascii(
			                            h, dd.iManufacturer, s, sizeof s) > 0)
				snprintf(ent.vendor, sizeof ent.vendor, "%s", (char *)s);
			if (dd.iProduct &&
			    libusb_get_string_descriptor_ascii(h, dd.iProduct, s, sizeof s) > 0)
				snprintf(ent.model, sizeof ent.model, "%s", (char *)s);
			if (dd.iSerialNumber && libusb_get_string_descriptor_ascii(
			                            h, dd.iSerialNumber, s, sizeof s) > 0)
				snprintf(ent.serial, sizeof ent.serial, "%s", (char *)s);
			libusb_close(h);
		}
		ent.usable = pc_usb3v_diagnose(libusb_get_device_speed(dev), open_status(oe), usbfs,
		                               dd.idVendor, dd.idProduct, bus, addr, ent.note,
		                               sizeof ent.note);
		/* Aravis names USB3 Vision devices vendor-model-serial */
		snprintf(ent.uri, sizeof ent.uri, "aravis:%s-%s-%s", ent.vendor, ent.model,
		         ent.serial);
		if (fn(ctx, &ent))
			break;
	}
	libusb_free_device_list(list, 1);
	libusb_exit(lc);
	return rc;
}
