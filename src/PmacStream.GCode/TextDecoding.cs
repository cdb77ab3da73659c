using System.Text;

namespace PmacStream.GCode;

/// <summary>Decodes comment and line bytes: UTF-8 when valid, otherwise GBK (what Chinese CAM tools write), otherwise Latin-1.</summary>
public static class TextDecoding
{
    private static readonly UTF8Encoding StrictUtf8 = new(false, true);
    private static readonly Lazy<Encoding?> Gbk = new(() =>
    {
        try
        {
            Encoding.RegisterProvider(CodePagesEncodingProvider.Instance);
            return Encoding.GetEncoding(936, EncoderFallback.ExceptionFallback, DecoderFallback.ExceptionFallback);
        }
        catch (Exception)
        {
            return null;
        }
    });

    /// <summary>Decodes bytes that may be UTF-8 or GBK.</summary>
    public static string Decode(ReadOnlySpan<byte> bytes)
    {
        if (!bytes.ContainsAnyInRange((byte)0x80, (byte)0xFF))
        {
            return Encoding.ASCII.GetString(bytes);
        }

        try
        {
            return StrictUtf8.GetString(bytes);
        }
        catch (DecoderFallbackException)
        {
        }

        if (Gbk.Value is { } gbk)
        {
            try
            {
                return gbk.GetString(bytes);
            }
            catch (DecoderFallbackException)
            {
            }
        }

        return Encoding.Latin1.GetString(bytes);
    }
}
