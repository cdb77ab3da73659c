using System.Buffers.Binary;

namespace PmacStream.Pmac;

/// <summary>
/// The VR_PMAC Ethernet packet protocol (Acc-54E style, what PComm32 speaks on TCP 1025): an 8-byte header
/// <c>RequestType, Request, wValue, wIndex, wLength</c> with big-endian 16-bit fields, then data for download requests.
/// Shared by <see cref="EthernetConnection"/> and the simulator's TCP server so both sides agree byte for byte.
/// </summary>
public static class VrPmac
{
    /// <summary>Header size in bytes.</summary>
    public const int HeaderSize = 8;

    /// <summary>Largest data part of one packet.</summary>
    public const int MaxData = 1492;

    /// <summary>Largest reply of GETRESPONSE/GETBUFFER/GETLINE; the rest waits for GETBUFFER.</summary>
    public const int MaxReply = 1400;

    /// <summary>Largest data part of a WRITEBUFFER packet.</summary>
    public const int MaxWriteBuffer = 1024;

    /// <summary>RequestType of host-to-PMAC requests (data follows the header).</summary>
    public const byte Download = 0x40;

    /// <summary>RequestType of PMAC-to-host requests (header only).</summary>
    public const byte Upload = 0xC0;

    /// <summary>Send a line without waiting for its reply text.</summary>
    public const byte SendLine = 0xB0;

    /// <summary>Fetch pending reply text.</summary>
    public const byte GetLine = 0xB1;

    /// <summary>Ctrl-X: discard pending replies.</summary>
    public const byte Flush = 0xB3;

    /// <summary>Run a command and return its reply.</summary>
    public const byte GetResponse = 0xBF;

    /// <summary>Is more reply data waiting (2-byte reply, first byte non-zero = yes).</summary>
    public const byte ReadReady = 0xC2;

    /// <summary>Control character in wValue; unterminated reply.</summary>
    public const byte CtrlResponse = 0xC4;

    /// <summary>Fetch the continuation of a long reply.</summary>
    public const byte GetBuffer = 0xC5;

    /// <summary>Many NUL-terminated program lines in one packet; 4-byte status reply.</summary>
    public const byte WriteBuffer = 0xC6;

    /// <summary>Writes an 8-byte header into <paramref name="destination"/>.</summary>
    public static void WriteHeader(Span<byte> destination, byte requestType, byte request, ushort wValue, ushort wIndex, ushort wLength)
    {
        destination[0] = requestType;
        destination[1] = request;
        BinaryPrimitives.WriteUInt16BigEndian(destination[2..], wValue);
        BinaryPrimitives.WriteUInt16BigEndian(destination[4..], wIndex);
        BinaryPrimitives.WriteUInt16BigEndian(destination[6..], wLength);
    }

    /// <summary>
    /// The 4-byte WRITEBUFFER status read as the little-endian DWORD PComm sees: byte 3 = 0x80 on error, byte 2 = ERR
    /// number, bytes 1..0 = the 0-based line within the packet (MSB, LSB). All zero means every line was accepted.
    /// </summary>
    public static void WriteBufferStatus(Span<byte> destination, int errorNumber, int lineInPacket)
    {
        destination[0] = (byte)(lineInPacket & 0xFF);
        destination[1] = (byte)((lineInPacket >> 8) & 0xFF);
        destination[2] = (byte)errorNumber;
        destination[3] = errorNumber == 0 ? (byte)0 : (byte)0x80;
    }

    /// <summary>Decodes a WRITEBUFFER status: false when every line was accepted.</summary>
    public static bool TryReadWriteBufferError(ReadOnlySpan<byte> status, out int errorNumber, out int lineInPacket)
    {
        errorNumber = status[2];
        lineInPacket = status[0] | (status[1] << 8);
        return (status[3] & 0x80) != 0;
    }

    /// <summary>
    /// Length of the first complete reply in <paramref name="bytes"/> by the controller's rule: up to and including
    /// ACK or LF; after BEL or STX, up to and including the next CR. -1 when no terminator has arrived yet.
    /// </summary>
    public static int ReplyLength(ReadOnlySpan<byte> bytes)
    {
        var error = false;
        for (var i = 0; i < bytes.Length; i++)
        {
            var b = bytes[i];
            if (error)
            {
                if (b == ReplyParser.Cr)
                {
                    return i + 1;
                }
            }
            else if (b == ReplyParser.Ack || b == 0x0A)
            {
                return i + 1;
            }
            else if (b == ReplyParser.Bel || b == 0x02)
            {
                error = true;
            }
        }

        return -1;
    }
}
