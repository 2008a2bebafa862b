#include "protocol.h"

#include <stdio.h>
#include <string.h>

/* Nine decimal digits always fit in 32 bits, so a long number is reported by value when it
 * is merely out of range, and only absurd ones are refused for their length. */
#define MOTOR_NUMBER_MAX_DIGITS 9

typedef struct {
  const char* at;
  const char* end;
} cursor;

static int is_space(char c) { return c == ' '; }
static int is_digit(char c) { return c >= '0' && c <= '9'; }

static size_t skip_spaces(cursor* c) {
  size_t skipped = 0;
  while (c->at < c->end && is_space(*c->at)) {
    ++c->at;
    ++skipped;
  }
  return skipped;
}

static motor_error parse_number(cursor* c, uint32_t* value) {
  size_t digits = 0;
  *value = 0;
  while (c->at < c->end && is_digit(*c->at)) {
    if (++digits > MOTOR_NUMBER_MAX_DIGITS) return MOTOR_ERROR_NUMBER_TOO_LONG;
    *value = *value * 10u + (uint32_t)(*c->at - '0');
    ++c->at;
  }
  if (digits == 0) return MOTOR_ERROR_SYNTAX;
  /* "12x" is not a number followed by garbage we could ignore: it is a typo. */
  if (c->at < c->end && !is_space(*c->at)) return MOTOR_ERROR_SYNTAX;
  return MOTOR_ERROR_NONE;
}

static motor_command rejected(char letter, motor_error error, uint32_t bad_value) {
  motor_command command;
  memset(&command, 0, sizeof command);
  command.kind = MOTOR_COMMAND_REJECTED;
  command.letter = letter;
  command.error = error;
  command.bad_value = bad_value;
  return command;
}

static motor_command parse_pulse(cursor* c) {
  uint32_t duration = 0, strength = 0;
  motor_error error;
  if (skip_spaces(c) == 0) return rejected('P', MOTOR_ERROR_SYNTAX, 0);
  if ((error = parse_number(c, &duration)) != MOTOR_ERROR_NONE) return rejected('P', error, 0);
  if (skip_spaces(c) == 0) return rejected('P', MOTOR_ERROR_SYNTAX, 0);
  if ((error = parse_number(c, &strength)) != MOTOR_ERROR_NONE) return rejected('P', error, 0);
  skip_spaces(c);
  if (c->at != c->end) return rejected('P', MOTOR_ERROR_SYNTAX, 0);
  if (duration < MOTOR_DURATION_MIN_MS || duration > MOTOR_DURATION_MAX_MS)
    return rejected('P', MOTOR_ERROR_DURATION_RANGE, duration);
  if (strength < MOTOR_STRENGTH_MIN || strength > MOTOR_STRENGTH_MAX)
    return rejected('P', MOTOR_ERROR_STRENGTH_RANGE, strength);

  motor_command command;
  memset(&command, 0, sizeof command);
  command.kind = MOTOR_COMMAND_PULSE;
  command.letter = 'P';
  command.duration_ms = (uint16_t)duration;
  command.strength = (uint8_t)strength;
  return command;
}

motor_command motor_parse_line(const char* line, size_t length) {
  cursor c = {line, line + length};
  motor_command command;
  memset(&command, 0, sizeof command);

  skip_spaces(&c);
  if (c.at == c.end) return command; /* blank: MOTOR_COMMAND_NONE */

  const char* token = c.at;
  while (c.at < c.end && !is_space(*c.at)) ++c.at;
  const size_t token_length = (size_t)(c.at - token);

  if (token_length == 1 && token[0] == 'P') return parse_pulse(&c);
  if (token_length == 1 && (token[0] == 'S' || token[0] == 'V')) {
    skip_spaces(&c);
    if (c.at != c.end) return rejected(token[0], MOTOR_ERROR_SYNTAX, 0);
    command.kind = token[0] == 'S' ? MOTOR_COMMAND_STOP : MOTOR_COMMAND_VERSION;
    command.letter = token[0];
    return command;
  }

  command = rejected(0, MOTOR_ERROR_UNKNOWN_COMMAND, 0);
  const size_t shown = token_length < sizeof command.token - 1 ? token_length : sizeof command.token - 1;
  memcpy(command.token, token, shown);
  command.token[shown] = '\0';
  return command;
}

void motor_parser_reset(motor_parser* parser) { memset(parser, 0, sizeof *parser); }

void motor_parser_mark_overrun(motor_parser* parser) {
  if (parser->pending_error == MOTOR_ERROR_NONE) parser->pending_error = MOTOR_ERROR_OVERRUN;
}

int motor_parser_feed(motor_parser* parser, uint8_t byte, motor_command* command) {
  if (byte == '\n' || byte == '\r') {
    if (parser->pending_error != MOTOR_ERROR_NONE) {
      *command = rejected(0, parser->pending_error, parser->bad_byte);
    } else {
      *command = motor_parse_line(parser->line, parser->length);
    }
    motor_parser_reset(parser);
    return command->kind != MOTOR_COMMAND_NONE;
  }
  /* The first fault of a line is the one reported; the rest of the line is dropped. */
  if (parser->pending_error != MOTOR_ERROR_NONE) return 0;
  if (byte < 0x20 || byte > 0x7e) {
    parser->pending_error = MOTOR_ERROR_BAD_BYTE;
    parser->bad_byte = byte;
    return 0;
  }
  if (parser->length == MOTOR_LINE_MAX) {
    parser->pending_error = MOTOR_ERROR_LINE_TOO_LONG;
    return 0;
  }
  parser->line[parser->length++] = (char)byte;
  return 0;
}

static const char* syntax_message(char letter) {
  switch (letter) {
    case 'P': return "ERR syntax: expected P <duration_ms> <strength>";
    case 'S': return "ERR syntax: S takes no arguments";
    case 'V': return "ERR syntax: V takes no arguments";
    default: return "ERR syntax";
  }
}

size_t motor_format_reply(const motor_command* command, char* out, size_t capacity) {
  int written = 0;
  switch (command->kind) {
    case MOTOR_COMMAND_NONE:
      if (capacity > 0) out[0] = '\0';
      return 0;
    case MOTOR_COMMAND_PULSE:
      written = snprintf(out, capacity, "OK P %u %u", (unsigned)command->duration_ms, (unsigned)command->strength);
      break;
    case MOTOR_COMMAND_STOP:
      written = snprintf(out, capacity, "OK S");
      break;
    case MOTOR_COMMAND_VERSION:
      written = snprintf(out, capacity, "OK V %s %d", MOTOR_FIRMWARE_NAME, MOTOR_PROTOCOL_VERSION);
      break;
    case MOTOR_COMMAND_REJECTED:
      switch (command->error) {
        case MOTOR_ERROR_UNKNOWN_COMMAND:
          written = snprintf(out, capacity, "ERR unknown command '%s': expected P, S or V", command->token);
          break;
        case MOTOR_ERROR_SYNTAX:
          written = snprintf(out, capacity, "%s", syntax_message(command->letter));
          break;
        case MOTOR_ERROR_NUMBER_TOO_LONG:
          written = snprintf(out, capacity, "ERR number longer than %d digits", MOTOR_NUMBER_MAX_DIGITS);
          break;
        case MOTOR_ERROR_DURATION_RANGE:
          written = snprintf(out, capacity, "ERR duration %lu ms out of range %u..%u",
                             (unsigned long)command->bad_value, MOTOR_DURATION_MIN_MS, MOTOR_DURATION_MAX_MS);
          break;
        case MOTOR_ERROR_STRENGTH_RANGE:
          written = snprintf(out, capacity, "ERR strength %lu out of range %u..%u", (unsigned long)command->bad_value,
                             MOTOR_STRENGTH_MIN, MOTOR_STRENGTH_MAX);
          break;
        case MOTOR_ERROR_LINE_TOO_LONG:
          written = snprintf(out, capacity, "ERR line longer than %u bytes", MOTOR_LINE_MAX);
          break;
        case MOTOR_ERROR_BAD_BYTE:
          written = snprintf(out, capacity, "ERR byte 0x%02X is not printable ASCII", (unsigned)command->bad_value);
          break;
        case MOTOR_ERROR_OVERRUN:
          written = snprintf(out, capacity, "ERR receive overrun: line lost, send it again");
          break;
        case MOTOR_ERROR_NONE:
          written = snprintf(out, capacity, "ERR internal: rejected without a reason");
          break;
      }
      break;
  }
  if (written < 0) written = 0;
  return (size_t)written < capacity ? (size_t)written : capacity - 1;
}

size_t motor_format_ready(char* out, size_t capacity) {
  const int written = snprintf(out, capacity, "READY %s %d", MOTOR_FIRMWARE_NAME, MOTOR_PROTOCOL_VERSION);
  if (written < 0) return 0;
  return (size_t)written < capacity ? (size_t)written : capacity - 1;
}

int motor_pulse_in_bounds(uint32_t duration_ms, uint32_t strength) {
  return duration_ms >= MOTOR_DURATION_MIN_MS && duration_ms <= MOTOR_DURATION_MAX_MS &&
         strength >= MOTOR_STRENGTH_MIN && strength <= MOTOR_STRENGTH_MAX;
}
