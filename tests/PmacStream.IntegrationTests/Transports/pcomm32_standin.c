/*
 * A stand-in for Delta Tau's Pcomm32.dll, for testing PmacStream's PComm32 marshalling on Linux.
 * Same exported names and (Windows 32-bit) argument types; it answers by forwarding to the PmacStream simulator's
 * TCP server with VR_PMAC GETRESPONSE (continuing with READREADY/GETBUFFER). The server address comes from the
 * environment variable PMACSTREAM_PCOMM_ADDR ("127.0.0.1:PORT") or from PmacStandInSetAddress (a test hook: .NET on
 * Unix does not change the native environment). Return values carry PComm's status nibble:
 * 0x80000000 EOT (ACK seen), 0xE0000000 error (buffer holds "ERRnnn"), 0xC0000000 timeout, 0xF0000000 fail.
 */
#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>
#include <errno.h>

#define MAXDEV 8
#define MAXREPLY 1400
#define ST_EOT 0x80000000u
#define ST_TIMEOUT 0xC0000000u
#define ST_ERROR 0xE0000000u
#define ST_FAIL 0xF0000000u

typedef void (*DOWNLOADMSGPROC)(char *str, int32_t newline);
typedef int32_t (*DOWNLOADGETPROC)(int32_t index, char *buffer, int32_t max);
typedef void (*DOWNLOADPROGRESS)(int32_t percent);

static int sockets[MAXDEV] = {-1, -1, -1, -1, -1, -1, -1, -1};
static char address[128];

void PmacStandInSetAddress(const char *addr)
{
    snprintf(address, sizeof address, "%s", addr);
}

static int send_packet(int s, uint8_t type, uint8_t request, uint16_t wvalue, const char *data, uint16_t len)
{
    unsigned char p[8 + 1500];
    uint16_t v = htons(wvalue), l = htons(len), z = 0;
    p[0] = type;
    p[1] = request;
    memcpy(p + 2, &v, 2);
    memcpy(p + 4, &z, 2);
    memcpy(p + 6, &l, 2);
    if (type == 0x40 && len > 0)
        memcpy(p + 8, data, len);
    size_t total = 8 + (type == 0x40 ? len : 0), sent = 0;
    while (sent < total) {
        ssize_t n = send(s, p + sent, total - sent, MSG_NOSIGNAL);
        if (n <= 0)
            return -1;
        sent += (size_t)n;
    }
    return 0;
}

/* Reply length by the controller's rule, or -1 while no terminator has arrived. */
static int reply_length(const unsigned char *b, int n)
{
    int error = 0;
    for (int i = 0; i < n; i++) {
        if (error) {
            if (b[i] == '\r')
                return i + 1;
        } else if (b[i] == 0x06 || b[i] == '\n') {
            return i + 1;
        } else if (b[i] == 0x07 || b[i] == 0x02) {
            error = 1;
        }
    }
    return -1;
}

/* Reads one reply packet; returns bytes, -2 on timeout, -1 on failure. */
static int recv_reply(int s, unsigned char *b, int max)
{
    int n = 0;
    while (n < max) {
        ssize_t got = recv(s, b + n, (size_t)(max - n), 0);
        if (got < 0)
            return (errno == EAGAIN || errno == EWOULDBLOCK) ? -2 : -1;
        if (got == 0)
            return -1;
        n += (int)got;
        if (reply_length(b, n) >= 0)
            break;
    }
    return n;
}

static int recv_exact(int s, unsigned char *b, int count)
{
    int n = 0;
    while (n < count) {
        ssize_t got = recv(s, b + n, (size_t)(count - n), 0);
        if (got <= 0)
            return -1;
        n += (int)got;
    }
    return n;
}

int32_t OpenPmacDevice(uint32_t dev)
{
    if (dev >= MAXDEV)
        return 0;
    if (sockets[dev] >= 0)
        return 1;
    const char *addr = address[0] ? address : getenv("PMACSTREAM_PCOMM_ADDR");
    if (!addr)
        return 0;
    char host[64];
    int port = 0;
    if (sscanf(addr, "%63[^:]:%d", host, &port) != 2)
        return 0;
    int s = socket(AF_INET, SOCK_STREAM, 0);
    if (s < 0)
        return 0;
    struct sockaddr_in sa;
    memset(&sa, 0, sizeof sa);
    sa.sin_family = AF_INET;
    sa.sin_port = htons((uint16_t)port);
    inet_pton(AF_INET, host, &sa.sin_addr);
    if (connect(s, (struct sockaddr *)&sa, sizeof sa) != 0) {
        close(s);
        return 0;
    }
    int one = 1;
    setsockopt(s, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    struct timeval tv = {2, 0};
    setsockopt(s, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    sockets[dev] = s;
    return 1;
}

int32_t ClosePmacDevice(uint32_t dev)
{
    if (dev >= MAXDEV || sockets[dev] < 0)
        return 0;
    close(sockets[dev]);
    sockets[dev] = -1;
    return 1;
}

static int32_t fail(uint32_t dev, uint32_t status)
{
    ClosePmacDevice(dev);
    return (int32_t)status;
}

int32_t PmacGetResponseA(uint32_t dev, char *response, uint32_t maxchar, char *command)
{
    if (dev >= MAXDEV || sockets[dev] < 0 || maxchar == 0)
        return (int32_t)ST_FAIL;
    int s = sockets[dev];
    size_t len = strlen(command);
    if (len > 1492 || send_packet(s, 0x40, 0xBF, 0, command, (uint16_t)len) != 0)
        return fail(dev, ST_FAIL);
    static unsigned char all[1 << 20];
    int total = 0;
    int n = recv_reply(s, all, MAXREPLY);
    if (n < 0)
        return fail(dev, n == -2 ? ST_TIMEOUT : ST_FAIL);
    total = n;
    while (reply_length(all, total) < 0) {
        unsigned char ready[2];
        if (send_packet(s, 0xC0, 0xC2, 0, NULL, 2) != 0 || recv_exact(s, ready, 2) != 2)
            return fail(dev, ST_FAIL);
        if (ready[0] == 0)
            continue;
        if (total + MAXREPLY > (int)sizeof all || send_packet(s, 0xC0, 0xC5, 0, NULL, MAXREPLY) != 0)
            return fail(dev, ST_FAIL);
        n = recv_reply(s, all + total, MAXREPLY);
        if (n < 0)
            return fail(dev, n == -2 ? ST_TIMEOUT : ST_FAIL);
        total += n;
    }
    unsigned char *bel = memchr(all, 0x07, (size_t)total);
    uint32_t out = 0, status = ST_EOT;
    if (bel) {
        /* PComm hands back the error text without BEL and CR. */
        status = ST_ERROR;
        for (unsigned char *p = bel + 1; p < all + total && *p != '\r' && out + 1 < maxchar; p++)
            response[out++] = (char)*p;
    } else {
        for (int i = 0; i < total && out + 1 < maxchar; i++)
            if (all[i] != 0x06)
                response[out++] = (char)all[i];
    }
    response[out] = 0;
    return (int32_t)(status | out);
}

int32_t PmacGetControlResponseA(uint32_t dev, char *response, uint32_t maxchar, char ctl)
{
    if (dev >= MAXDEV || sockets[dev] < 0 || maxchar == 0)
        return (int32_t)ST_FAIL;
    int s = sockets[dev];
    if (send_packet(s, 0xC0, 0xC4, (uint16_t)(unsigned char)ctl, NULL, 0) != 0)
        return fail(dev, ST_FAIL);
    unsigned char b[MAXREPLY];
    ssize_t n = recv(s, b, sizeof b, 0);
    if (n <= 0)
        return fail(dev, ST_FAIL);
    uint32_t out = 0;
    for (ssize_t i = 0; i < n && out + 1 < maxchar; i++)
        if (b[i] != 0)
            response[out++] = (char)b[i];
    response[out] = 0;
    return (int32_t)(ST_EOT | out);
}

void PmacFlush(uint32_t dev)
{
    if (dev >= MAXDEV || sockets[dev] < 0)
        return;
    unsigned char one;
    if (send_packet(sockets[dev], 0x40, 0xB3, 0, NULL, 0) == 0)
        recv_exact(sockets[dev], &one, 1);
}

/* Sends a file line by line (comments stripped, blank lines skipped); no macro processing in the stand-in. */
int32_t PmacDownloadA(uint32_t dev, DOWNLOADMSGPROC msg, DOWNLOADGETPROC get, DOWNLOADPROGRESS prog, char *filename,
                      int32_t macro, int32_t map, int32_t log, int32_t dnld)
{
    (void)get; (void)macro; (void)map; (void)log;
    FILE *f = fopen(filename, "r");
    char line[1024], reply[4096], text[1200];
    if (!f) {
        if (msg) {
            snprintf(text, sizeof text, "cannot open %s", filename);
            msg(text, 1);
        }
        return 0;
    }
    int count = 0, lineno = 0, sent = 0;
    while (fgets(line, sizeof line, f))
        count++;
    rewind(f);
    while (fgets(line, sizeof line, f)) {
        lineno++;
        char *semi = strchr(line, ';');
        if (semi)
            *semi = 0;
        size_t n = strlen(line);
        while (n > 0 && (line[n - 1] == '\n' || line[n - 1] == '\r' || line[n - 1] == ' ' || line[n - 1] == '\t'))
            line[--n] = 0;
        if (n == 0)
            continue;
        if (dnld) {
            int32_t r = PmacGetResponseA(dev, reply, sizeof reply, line);
            uint32_t st = (uint32_t)r & 0xF0000000u;
            if (st != ST_EOT) {
                if (msg) {
                    snprintf(text, sizeof text, "%s at line %d: %s", st == ST_ERROR ? reply : "link failure", lineno, line);
                    msg(text, 1);
                }
                fclose(f);
                return 0;
            }
            sent++;
        }
        if (prog && count > 0)
            prog(lineno * 100 / count);
    }
    fclose(f);
    if (msg) {
        snprintf(text, sizeof text, "%d lines downloaded", sent);
        msg(text, 1);
    }
    return 1;
}
