!> A face shaken by an earthquake record: a base acceleration (or velocity) time history read
!> from a CSV file, times a vector `scale` (its direction and units), applied on the face.
!>
!> - Without `vp` and `vs`, a **rigid base**: every velocity component of the face's nodes is
!>   prescribed, the record's motion along `scale` and zero across it, as a velocity face that
!>   changes in time. The impulse that takes is the face's reaction (history.csv: the base
!>   shear and normal force) and its work, at the mean velocity of the step, is work of the
!>   loads. A wave that comes back down reflects at the base (the rigid bedrock of the
!>   closed-form transfer function 1 / cos(omega H / v)).
!> - With `vp` and `vs`, a **compliant base** (Joyner and Chen 1975): the ground beyond the
!>   face is an elastic half-space of those wave speeds and of the density of the material at
!>   the face, the record is its outcrop motion (twice the incident wave), and the face
!>   applies the traction rho v (v_out - v), v the node's velocity: a dashpot that takes the
!>   waves leaving the domain (as an absorbing face) and pulls the node towards the outcrop
!>   motion. On the grid, as the absorbing face, the dashpot of a node of mass m is
!>   2 m v_wave / dx, implicit: v = (v* + b v_out) / (1 + b), b = 2 v_wave dt / dx, v_out at the
!>   middle of the step. Of the impulse m (v - v*) = m b (v_out - v), the part m b v_out
!>   enters as work of the loads and the part - m b v leaves with what the faces stop, each at
!>   the mean velocity of the step.
!>
!> The record's rows are (time, value); an acceleration record is integrated from rest
!> (exactly: linear between the rows), a velocity record is linear between them. Before its
!> first time the face is at rest (an acceleration record) or at the first velocity; after
!> its last, the velocity stays at the last one (a record whose velocity does not return to
!> zero moves the base on: correct its baseline first).
module mpm_boundary_seismic
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: fmt_real, fmt_vector, int_text
    use mpm_case_cursor, only: cursor_type
    use mpm_time_function, only: read_table
    use mpm_boundary, only: boundary_type, face_nodes_type, boundary_key_width
    use mpm_boundary_absorbing, only: absorbing_boundary_type
    implicit none
    private
    public :: seismic_boundary_type, record_acceleration, record_velocity

    integer, parameter :: record_acceleration = 1, record_velocity = 2
        !! kinds of record
    character(len=*), parameter :: record_names(2) = [character(len=12) :: "acceleration", &
        "velocity"]
        !! name of each kind in the case file

    !> A rigid or compliant base shaken by a record.
    type, extends(absorbing_boundary_type) :: seismic_boundary_type
        character(len=:), allocatable :: file
            !! the record's CSV file
        integer :: record = record_acceleration
            !! record_acceleration or record_velocity
        real(wp) :: scale(3) = 0.0_wp
            !! the face's motion per unit of the record's value (1..dim) [-]
        integer :: dim = 2
            !! space dimensions
        logical :: compliant = .false.
            !! vp and vs given: a compliant base
        real(wp), allocatable :: times(:)
            !! the record's times, increasing [s]
        real(wp), allocatable :: values(:)
            !! its values [m/s2 or m/s per unit of scale]
        real(wp), allocatable :: speed(:)
            !! the velocity at each time, the record integrated from rest (an acceleration
            !! record) or its values (a velocity record) [m/s per unit of scale]
    contains
        procedure, nopass :: names => seismic_names
        procedure, nopass :: keys => seismic_keys
        procedure, nopass :: example => seismic_example
        procedure, nopass :: purpose => seismic_purpose
        procedure, nopass :: needs => seismic_needs
        procedure :: read => seismic_read
        procedure :: summary => seismic_summary
        procedure :: nodes => seismic_nodes
        procedure :: act => seismic_act
        procedure :: velocity_at => seismic_velocity_at
        !> The record's velocity at a time, per unit of scale [m/s].
        procedure :: record_speed => seismic_record_speed
    end type seismic_boundary_type

contains

    !> "seismic"
    pure subroutine seismic_names(list)
        character(len=boundary_key_width), allocatable, intent(out) :: list(:)
            !! the names

        list = [character(len=boundary_key_width) :: "seismic"]
    end subroutine seismic_names

    !> "file", "record", "scale", "vp", "vs"
    pure subroutine seismic_keys(list)
        character(len=boundary_key_width), allocatable, intent(out) :: list(:)
            !! the keys

        list = [character(len=boundary_key_width) :: "file", "record", "scale", "vp", "vs"]
    end subroutine seismic_keys

    !> The object form, for messages.
    pure function seismic_example() result(text)
        character(len=:), allocatable :: text
            !! an example face object

        text = '{"type": "seismic", "file": "record.csv", "record": "acceleration", ' &
            //'"scale": [9.81, 0]} (with "vp", "vs": a compliant base)'
    end function seismic_example

    !> What it is for, for messages.
    pure function seismic_purpose() result(text)
        character(len=:), allocatable :: text
            !! "a face ..."

        text = "a face shaken by an earthquake record"
    end function seismic_purpose

    !> What the name alone lacks.
    pure function seismic_needs() result(text)
        character(len=:), allocatable :: text
            !! the missing parameters

        text = "a record file and its scale"
    end function seismic_needs

    !> `file` (required: rows "time, value"), `record` (required: "acceleration" or
    !> "velocity"), `scale` (required: dim finite numbers, not all zero), and `vp`, `vs`
    !> together or not at all (a compliant base; checked as for an absorbing face).
    subroutine seismic_read(self, face, dim, error)
        class(seismic_boundary_type), intent(inout) :: self
            !! the condition
        type(cursor_type), intent(in) :: face
            !! the face object, its keys checked
        integer, intent(in) :: dim
            !! space dimensions
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        integer :: k

        self%dim = dim
        call face%get_choice("record", record_names, [record_acceleration, record_velocity], &
            self%record, error, required=.true.)
        if (allocated(error)) return
        call face%get_vector("scale", dim, self%scale, error, required=.true.)
        if (allocated(error)) return
        if (all(self%scale(1:dim) == 0.0_wp)) then
            call face%fail(error, face%key_path("scale")//" = "//fmt_vector(self%scale(1:dim)) &
                //" moves nothing: give the direction and units of the record, e.g. [9.81, " &
                //"0] for a horizontal acceleration record in g")
            return
        end if
        self%file = ""
        call face%get_path("file", 0, self%file, error, required=.true.)
        if (allocated(error)) return
        call read_table(face, "file", self%file, trim(record_names(self%record)), self%times, &
            self%values, error)
        if (allocated(error)) return
        self%compliant = face%has("vp") .or. face%has("vs")
        if (self%compliant) then
            if (.not. (face%has("vp") .and. face%has("vs"))) then
                call face%fail(error, face%path//" gives "//trim(merge("vp", "vs", &
                    face%has("vp")))//" without "//trim(merge("vs", "vp", face%has("vp"))) &
                    //": a compliant base needs both wave speeds of the ground beyond the " &
                    //"face (or neither: a rigid base)")
                return
            end if
            call self%absorbing_boundary_type%read(face, dim, error)
            if (allocated(error)) return
        end if
        ! the velocity at each row
        allocate (self%speed(size(self%times)))
        if (self%record == record_velocity) then
            self%speed = self%values
        else
            self%speed(1) = 0.0_wp
            do k = 2, size(self%times)
                self%speed(k) = self%speed(k - 1) + 0.5_wp*(self%values(k - 1) &
                    + self%values(k))*(self%times(k) - self%times(k - 1))
            end do
        end if
    end subroutine seismic_read

    !> ' (acceleration record "file.csv", 2000 rows over 0 - 20 s, scale (9.81, 0); compliant:
    !> vp = 300 m/s, vs = 160 m/s)'
    pure function seismic_summary(self) result(text)
        class(seismic_boundary_type), intent(in) :: self
            !! the condition
        character(len=:), allocatable :: text
            !! the words after the name

        text = " ("//trim(record_names(self%record))//' record "'//self%file//'", ' &
            //int_text(size(self%times))//" rows over "//fmt_real(self%times(1))//" - " &
            //fmt_real(self%times(size(self%times)))//" s, scale "// &
            fmt_vector(self%scale(1:self%dim))
        if (self%compliant) then
            text = text//"; compliant base: vp = "//fmt_real(self%vp)//" m/s, vs = " &
                //fmt_real(self%vs)//" m/s)"
        else
            text = text//"; rigid base)"
        end if
    end function seismic_summary

    !> A rigid base: every component prescribed, changing in time; a compliant base: nothing
    !> held, the face acts on its nodes. A wall either way.
    pure function seismic_nodes(self, axis, dim) result(nodes)
        class(seismic_boundary_type), intent(in) :: self
            !! the condition
        integer, intent(in) :: axis
            !! axis normal to the face
        integer, intent(in) :: dim
            !! space dimensions
        type(face_nodes_type) :: nodes
            !! its action on the face's nodes

        nodes%keeps_particles = .true.
        if (self%compliant) then
            nodes%acts = .true.
        else
            nodes%held(1:dim) = .true.
            nodes%prescribed = .true.
            nodes%varies = .true.
            nodes%velocity = self%velocity_at(0.0_wp, dim)
        end if
    end function seismic_nodes

    !> The record's velocity at time t per unit of scale: exact integral of the piecewise-linear
    !> acceleration from rest, or the piecewise-linear velocity.
    pure real(wp) function seismic_record_speed(self, t) result(speed)
        class(seismic_boundary_type), intent(in) :: self
            !! the condition
        real(wp), intent(in) :: t
            !! time [s]

        integer :: lo, hi, mid, n
        real(wp) :: tau, span

        speed = 0.0_wp
        if (.not. allocated(self%times)) return
        n = size(self%times)
        if (t <= self%times(1)) then
            speed = self%speed(1)
            return
        end if
        if (t >= self%times(n)) then
            speed = self%speed(n)
            return
        end if
        lo = 1
        hi = n
        do while (hi - lo > 1)
            mid = (lo + hi)/2
            if (self%times(mid) <= t) then
                lo = mid
            else
                hi = mid
            end if
        end do
        tau = t - self%times(lo)
        span = self%times(hi) - self%times(lo)
        if (self%record == record_velocity) then
            speed = self%values(lo) + (self%values(hi) - self%values(lo))*tau/span
        else
            speed = self%speed(lo) + self%values(lo)*tau &
                + 0.5_wp*(self%values(hi) - self%values(lo))*tau**2/span
        end if
    end function seismic_record_speed

    !> The face's velocity at time t: the record's times scale.
    pure function seismic_velocity_at(self, time, dim) result(velocity)
        class(seismic_boundary_type), intent(in) :: self
            !! the condition
        real(wp), intent(in) :: time
            !! time [s]
        integer, intent(in) :: dim
            !! space dimensions
        real(wp) :: velocity(3)
            !! velocity (1..dim) [m/s]

        velocity = 0.0_wp
        velocity(1:dim) = self%record_speed(time)*self%scale(1:dim)
    end function seismic_velocity_at

    !> The compliant base: implicit dashpots towards the outcrop velocity of the middle of
    !> the step, per component (vp normal to the face, vs along it), the held components left
    !> alone. What comes in is booked as given, what leaves as taken, each at the mean
    !> velocity of the step.
    pure subroutine seismic_act(self, axis, dim, time, dt, dx, mass, area, held, momentum, &
        velocity, acceleration, displacement, taken, given)
        class(seismic_boundary_type), intent(in) :: self
            !! the condition
        integer, intent(in) :: axis
            !! axis normal to the face
        integer, intent(in) :: dim
            !! space dimensions
        real(wp), intent(in) :: time
            !! time at the start of the step [s]
        real(wp), intent(in) :: dt
            !! time step [s]
        real(wp), intent(in) :: dx
            !! grid spacing [m]
        real(wp), intent(in) :: mass(:)
            !! mass of each node of the face (n) [kg]
        real(wp), intent(in) :: area(:)
            !! face area each node stands for (n) [m2; m in 2D]
        logical, intent(in) :: held(:, :)
            !! components another face holds (dim, n)
        real(wp), intent(inout) :: momentum(:, :)
            !! momentum (dim, n) [kg m/s]
        real(wp), intent(inout) :: velocity(:, :)
            !! velocity (dim, n) [m/s]
        real(wp), intent(inout) :: acceleration(:, :)
            !! acceleration of the step (dim, n) [m/s2]
        real(wp), intent(inout) :: displacement(:, :)
            !! displacement of each node since the start (dim, n) [m]: the state of a law
            !! with springs, which updates it; the others leave it alone
        real(wp), intent(out) :: taken
            !! energy the dashpots took in this step [J]
        real(wp), intent(out) :: given
            !! work of the outcrop motion in this step [J]

        real(wp) :: b(3), v(3), v0(3), mean(3), outcrop(3)
        integer :: i

        taken = 0.0_wp
        given = 0.0_wp
        if (.not. self%compliant) return
        b = 2.0_wp*self%vs*dt/dx
        b(axis) = 2.0_wp*self%vp*dt/dx
        outcrop = self%velocity_at(time + 0.5_wp*dt, dim)
        do i = 1, size(mass)
            v(1:dim) = merge(velocity(:, i), (velocity(:, i) + b(1:dim)*outcrop(1:dim)) &
                /(1.0_wp + b(1:dim)), held(:, i))
            v0(1:dim) = velocity(:, i) - dt*acceleration(:, i)
            mean(1:dim) = merge(0.0_wp, 0.5_wp*(v0(1:dim) + v(1:dim)), held(:, i))
            given = given + mass(i)*sum(b(1:dim)*outcrop(1:dim)*mean(1:dim))
            taken = taken + mass(i)*sum(b(1:dim)*v(1:dim)*mean(1:dim))
            acceleration(:, i) = acceleration(:, i) + (v(1:dim) - velocity(:, i))/dt
            velocity(:, i) = v(1:dim)
            momentum(:, i) = mass(i)*v(1:dim)
        end do
    end subroutine seismic_act

end module mpm_boundary_seismic
